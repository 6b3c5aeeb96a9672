#include "raster/scenes.hpp"

#include <cmath>
#include <cstdio>
#include <glm/gtc/matrix_transform.hpp>
#include <map>
#include <vector>

#include "scene_blending.hpp"
#include "scene_list.hpp"

namespace raster {

glm::mat4 sceneProjection(const SceneOptions& o) {
    const float fov_degrees = o.fovDegrees.value_or(60.0f);
    return glm::perspectiveRH_ZO(glm::radians(fov_degrees), float(o.width) / float(o.height), 0.1f, 100.0f);
}

glm::mat4 sceneView(const SceneCamera& c) {
    return glm::lookAtRH(c.eye, c.target, glm::vec3(0, 1, 0));
}

namespace {

// A time in seconds as an error message shows it: %g, so -1 and 0.5 read as such, NaN as nan.
std::string secondsText(double seconds) {
    char text[48];
    std::snprintf(text, sizeof text, "%.9g s", seconds);
    return text;
}

}  // namespace

std::string finiteValueProblem(double value) {
    char text[64];
    std::snprintf(text, sizeof text, "%g", value);
    if (std::isnan(value)) return std::string(text) + " is not a number";
    if (std::isinf(value)) return std::string(text) + " is infinite";
    if (!std::isfinite(float(value))) return std::string(text) + " is too large for a float";
    return "";
}

std::string fogValueProblem(double value) {
    if (std::isfinite(value) && value < 0.0) {
        char text[64];
        std::snprintf(text, sizeof text, "%g is negative", value);
        return text;
    }
    return finiteValueProblem(value);
}

std::string sceneLightProblem(const SceneLight& light) {
    for (int c = 0; c < 3; ++c)
        if (std::string problem = finiteValueProblem(light.value[c]); !problem.empty()) return problem;
    const glm::vec3 n = glm::normalize(light.value);
    if (!light.point && !(std::isfinite(n.x) && std::isfinite(n.y) && std::isfinite(n.z))) {
        char text[160];
        std::snprintf(text, sizeof text, "the direction (%g, %g, %g) has no length", double(light.value.x),
                      double(light.value.y), double(light.value.z));
        return text;
    }
    return "";
}

const std::vector<std::string_view>& volumeLightScenes() {
    static const std::vector<std::string_view> names = {"media", "cloud", "cloud-point"};
    return names;
}

void Scene::advance(double seconds) {
    RASTER_REQUIRE(std::isfinite(seconds) && seconds >= 0.0, InvalidArgument,
                   "scene '" + std::string(name()) + "': advance by " + secondsText(seconds) +
                       ": the time must be finite and >= 0");
    advanceBy(seconds);
}

void beginSceneFrame(Context& context, RenderTarget& color, DepthTarget& depth) {
    context.clearRenderTarget(color, {0, 0, 0, 1});
    context.clearDepthTarget(depth, 1.0f);
    context.setRenderTargets(&color, &depth);
    context.setViewport({0, 0, float(color.width()), float(color.height()), 0, 1});
    RasterizerState rs;
    rs.cullMode = CullMode::None;
    context.setRasterizerState(rs);
    context.setCoverageTest(nullptr);
}

FullScreenTriangle::FullScreenTriangle() {
    const std::vector<glm::vec2> corners = {{-1, -1}, {3, -1}, {-1, 3}};
    vertices = VertexBuffer::create(corners);
    const InputElementDesc desc[] = {{"POSITION", 0, Format::R32G32_FLOAT, 0, 0}};
    layout = InputLayout(desc);
}

void FullScreenTriangle::bind(Context& context) const {
    context.setBlendState(BlendState::opaque());
    context.setPrimitiveTopology(Topology::TriangleList);
    context.setDepthStencilState(DepthStencilState::disabled());
    context.setInputLayout(&layout);
    context.setVertexBuffer(0, &vertices);
}

namespace {

// Filled before main by the labs' static registrations, so a function-local static: the order in
// which translation units initialise is unspecified. Read-only once main runs.
std::map<std::string, SceneEntry, std::less<>>& registry() {
    static std::map<std::string, SceneEntry, std::less<>> entries;
    return entries;
}

// The library's own scenes, in the order listings show them: the lecture's first.
struct BuiltinScene {
    std::string_view name;
    SceneCamera camera;
    std::unique_ptr<Scene> (*make)(std::string_view name, const SceneOptions& options);  // options checked
};

template <std::unique_ptr<Scene> (*make)(const SceneOptions&)>
std::unique_ptr<Scene> makeNamed(std::string_view, const SceneOptions& options) {
    return make(options);
}

void requireCubes(const SceneOptions& options) {
    RASTER_REQUIRE(options.cubes <= 1024, InvalidArgument,
                   "cube count " + std::to_string(options.cubes) + " per side is above 1024");
}
std::unique_ptr<Scene> makeFogChecked(std::string_view, const SceneOptions& options) {
    requireCubes(options);
    return makeFogScene(options);
}
std::unique_ptr<Scene> makeFogFigureChecked(std::string_view name, const SceneOptions& options) {
    requireCubes(options);
    return makeFogFigureScene(name, options);
}
std::unique_ptr<Scene> makeCloudChecked(std::string_view name, const SceneOptions& options) {
    requireCubes(options);
    return makeCloudScene(name, options);
}
std::unique_ptr<Scene> makeMediaChecked(std::string_view, const SceneOptions& options) {
    requireCubes(options);
    return makeMediaClosedFormScene(options);
}

// The options' medium: every component a finite float >= 0, and q/σ finite where σ > 0 (the fog's
// colour seen to infinity; FogMedium's domain).
void requireFogMedium(const SceneOptions& o) {
    const auto check = [](const char* what, const glm::vec3& v) {
        for (int c = 0; c < 3; ++c) {
            const std::string problem = fogValueProblem(v[c]);
            RASTER_REQUIRE(problem.empty(), InvalidArgument,
                           std::string("fog ") + what + " " + "RGB"[c] + ": " + problem);
        }
    };
    if (o.fogSigma) check("sigma", *o.fogSigma);
    if (o.fogSource) check("source", *o.fogSource);
    if (o.fogFalloff) {
        const std::string problem = fogValueProblem(*o.fogFalloff);
        RASTER_REQUIRE(problem.empty(), InvalidArgument, "fog falloff: " + problem);
    }
    if (o.fogSigma && o.fogSource)
        for (int c = 0; c < 3; ++c) {
            const float sigma = (*o.fogSigma)[c], q = (*o.fogSource)[c];
            char text[160];
            std::snprintf(text, sizeof text, "fog source %g over sigma %g (channel %c) is not a finite float",
                          double(q), double(sigma), "RGB"[c]);
            RASTER_REQUIRE(sigma == 0.0f || std::isfinite(q / sigma), InvalidArgument, text);
        }
}

// The options' light: for a scene that marches one, its numbers finite, a direction not 0, the
// intensity's components finite and ≥ 0.
void requireLight(std::string_view name, const SceneOptions& o) {
    if (!o.light && !o.lightIntensity) return;
    const auto& takes = volumeLightScenes();
    if (std::find(takes.begin(), takes.end(), name) == takes.end()) {
        std::string list;
        for (std::string_view n : takes) list += (list.empty() ? "" : ", ") + std::string(n);
        throw Error(ErrorCode::InvalidArgument,
                    "light: scene '" + std::string(name) + "' has no volume light (the scenes with one: " + list + ")");
    }
    if (o.light) {
        const std::string problem = sceneLightProblem(*o.light);
        RASTER_REQUIRE(problem.empty(), InvalidArgument, "light: " + problem);
    }
    if (o.lightIntensity)
        for (int c = 0; c < 3; ++c) {
            const std::string problem = fogValueProblem((*o.lightIntensity)[c]);
            RASTER_REQUIRE(problem.empty(), InvalidArgument,
                           std::string("light intensity ") + "RGB"[c] + ": " + problem);
        }
}

const std::vector<BuiltinScene>& builtinScenes() {
    static const std::vector<BuiltinScene> scenes = [] {
        std::vector<BuiltinScene> list = {
            {"fire", kFireCamera, makeNamed<makeFireScene>},
            {"smoke", kSmokeCamera, makeNamed<makeSmokeScene>},
            {"sprites", kSpritesCamera, makeNamed<makeSpritesScene>},
            {"forest", kForestCamera, makeNamed<makeForestScene>},
            {"particles", kParticlesCamera, makeNamed<makeParticlesScene>},
            {"fog", kFogCamera, makeFogChecked},
        };
        for (std::string_view name : fogFigureNames()) list.push_back({name, kFogCamera, makeFogFigureChecked});
        list.push_back({"media-closed-form", kMediaCamera, makeMediaChecked});
        list.push_back({"media", kMediaMarchCamera, makeNamed<makeMediaMarchScene>});
        list.push_back({"cloud", kCloudCamera, makeCloudChecked});
        list.push_back({"cloud-point", kCloudCamera, makeCloudChecked});
        list.push_back({"smoke-volume", kSmokeCamera, makeNamed<makeSmokeVolumeScene>});
        for (std::string_view name : mediaFigureNames())
            list.push_back({name, name == "media-absorption" || name == "media-emission" ? kMediaFigureCamera
                                                                                         : kMediaPanelCamera,
                            makeMediaFigureScene});
        for (std::string_view name : slideFigureNames()) list.push_back({name, kMediaMarchCamera, makeSlideFigureScene});
        for (std::string_view name : blendingSceneNames())
            list.push_back({name, kBlendCamera, makeBlendingScene});
        return list;
    }();
    return scenes;
}

const BuiltinScene* findBuiltinScene(std::string_view name) {
    for (const BuiltinScene& scene : builtinScenes())
        if (scene.name == name) return &scene;
    return nullptr;
}

std::string knownScenes() {
    std::string text;
    for (const std::string& n : sceneNames()) text += (text.empty() ? "" : ", ") + n;
    return text;
}

[[noreturn]] void unknownScene(std::string_view name) {
    throw Error(ErrorCode::InvalidArgument,
                "unknown scene '" + std::string(name) + "' (known: " + knownScenes() + ")");
}

}  // namespace

void registerScene(SceneEntry entry) {
    const std::string& n = entry.name;
    RASTER_REQUIRE(!n.empty() && n.size() <= 64, InvalidArgument,
                   "a registered scene needs a name of 1..64 characters");
    for (char c : n)
        RASTER_REQUIRE((c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_' || c == '-' || c == '@',
                       InvalidArgument, "scene name '" + n + "' may hold only a-z, 0-9, _, - and @");
    RASTER_REQUIRE(!findBuiltinScene(n) && !registry().contains(n), InvalidArgument,
                   "scene '" + n + "' is registered twice (two labs of one name?)");
    RASTER_REQUIRE(entry.make != nullptr, InvalidArgument,
                   "scene '" + n + "' is registered without a factory");
    registry().emplace(n, std::move(entry));
}

const SceneEntry* findRegisteredScene(std::string_view name) {
    const auto it = registry().find(name);
    return it == registry().end() ? nullptr : &it->second;
}

std::string solutionSceneOf(std::string_view name) {
    if (name.find('@') != std::string_view::npos) return {};
    std::string solution = std::string(name) + "@solution";
    return findRegisteredScene(solution) ? solution : std::string();
}

std::vector<std::string> sceneNames() {
    std::vector<std::string> names;
    for (const BuiltinScene& scene : builtinScenes()) names.emplace_back(scene.name);
    for (const auto& [name, entry] : registry()) names.push_back(name);
    return names;
}

SceneCamera defaultCamera(std::string_view name) {
    if (const BuiltinScene* scene = findBuiltinScene(name)) return scene->camera;
    if (const SceneEntry* entry = findRegisteredScene(name)) return entry->camera;
    unknownScene(name);
}

std::unique_ptr<Scene> makeScene(std::string_view name, const SceneOptions& options) {
    RASTER_REQUIRE(options.width > 0 && options.height > 0 && options.width <= RenderTarget::kMaxSize &&
                       options.height <= RenderTarget::kMaxSize,
                   InvalidArgument,
                   "image size " + std::to_string(options.width) + "x" + std::to_string(options.height) +
                       " is outside 1.." + std::to_string(RenderTarget::kMaxSize));
    if (options.camera) {
        const SceneCamera& c = *options.camera;
        const glm::vec3 view = c.target - c.eye;
        const auto text = [](glm::vec3 v) {
            return "(" + std::to_string(v.x) + ", " + std::to_string(v.y) + ", " + std::to_string(v.z) + ")";
        };
        // Look-at needs a direction, and one that is not vertical (+y is its up).
        bool finite = true;
        for (int k = 0; k < 3; ++k) finite = finite && std::isfinite(c.eye[k]) && std::isfinite(c.target[k]);
        RASTER_REQUIRE(
            finite && view.x * view.x + view.z * view.z > 1e-12f * glm::dot(view, view) &&
                glm::dot(view, view) > 0.0f,
            InvalidArgument,
            "camera eye " + text(c.eye) + " and target " + text(c.target) +
                " do not make a view direction (they must be finite, apart, and not one above the other)");
    }
    if (options.time) {
        const double t = *options.time;
        RASTER_REQUIRE(
            std::isfinite(t) && t >= 0.0 && t <= kMaxStartTime, InvalidArgument,
            "start time " + secondsText(t) + " is outside [0, " + secondsText(kMaxStartTime) + "]");
    }
    if (options.fovDegrees) {
        const float fov = *options.fovDegrees;
        RASTER_REQUIRE(std::isfinite(fov) && fov > 0.0f && fov <= 179.0f, InvalidArgument,
                       "field of view " + std::to_string(fov) + " degrees is outside (0, 179]");
    }
    if (options.count) {
        RASTER_REQUIRE(*options.count <= 50'000'000, InvalidArgument,
                       "particle count " + std::to_string(*options.count) + " is above 50000000");
    }
    requireFogMedium(options);
    requireLight(name, options);
    if (const BuiltinScene* builtin = findBuiltinScene(name)) {
        std::unique_ptr<Scene> scene = builtin->make(name, options);
        RASTER_CHECK(scene && scene->name() == name);
        return scene;
    }
    const SceneEntry* entry = findRegisteredScene(name);
    if (!entry) unknownScene(name);
    std::unique_ptr<Scene> scene = entry->make(entry->name, options);
    RASTER_CHECK(scene && scene->name() == entry->name);
    return scene;
}

}  // namespace raster
