#include "raster/scenes.hpp"

#include <cmath>
#include <cstdio>
#include <map>

#include <glm/gtc/matrix_transform.hpp>

#include "scene_list.hpp"

namespace raster {

glm::mat4 sceneProjection(const SceneOptions& o) {
    return glm::perspectiveRH_ZO(glm::radians(60.0f), float(o.width) / float(o.height), 0.1f, 100.0f);
}

glm::mat4 sceneView(const SceneCamera& c) { return glm::lookAtRH(c.eye, c.target, glm::vec3(0, 1, 0)); }

namespace {

// A time in seconds as an error message shows it: %g, so -1 and 0.5 read as such, NaN as nan.
std::string secondsText(double seconds) {
    char text[48];
    std::snprintf(text, sizeof text, "%.9g s", seconds);
    return text;
}

}  // namespace

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

namespace {

// Filled before main by the labs' static registrations, so a function-local static: the order in
// which translation units initialise is unspecified. Read-only once main runs.
std::map<std::string, SceneEntry, std::less<>>& registry() {
    static std::map<std::string, SceneEntry, std::less<>> entries;
    return entries;
}

std::string knownScenes() {
    std::string text;
    for (const std::string& n : sceneNames()) text += (text.empty() ? "" : ", ") + n;
    return text;
}

[[noreturn]] void unknownScene(std::string_view name) {
    throw Error(ErrorCode::InvalidArgument, "unknown scene '" + std::string(name) + "' (known: " + knownScenes() + ")");
}

}  // namespace

void registerScene(SceneEntry entry) {
    const std::string& n = entry.name;
    RASTER_REQUIRE(!n.empty() && n.size() <= 64, InvalidArgument, "a registered scene needs a name of 1..64 characters");
    for (char c : n)
        RASTER_REQUIRE((c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_' || c == '-' || c == '@',
                       InvalidArgument, "scene name '" + n + "' may hold only a-z, 0-9, _, - and @");
    RASTER_REQUIRE(n != "fire" && n != "smoke" && n != "particles" && n != "fog" && !registry().contains(n), InvalidArgument,
                   "scene '" + n + "' is registered twice (two labs of one name?)");
    RASTER_REQUIRE(entry.make != nullptr, InvalidArgument, "scene '" + n + "' is registered without a factory");
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
    std::vector<std::string> names = {"fire", "smoke", "particles", "fog"};
    for (const auto& [name, entry] : registry()) names.push_back(name);
    return names;
}

SceneCamera defaultCamera(std::string_view name) {
    if (name == "fire") return kFireCamera;
    if (name == "smoke") return kSmokeCamera;
    if (name == "particles") return kParticlesCamera;
    if (name == "fog") return kFogCamera;
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
        RASTER_REQUIRE(finite && view.x * view.x + view.z * view.z > 1e-12f * glm::dot(view, view) &&
                           glm::dot(view, view) > 0.0f,
                       InvalidArgument,
                       "camera eye " + text(c.eye) + " and target " + text(c.target) +
                           " do not make a view direction (they must be finite, apart, and not one above the other)");
    }
    if (options.time) {
        const double t = *options.time;
        RASTER_REQUIRE(std::isfinite(t) && t >= 0.0 && t <= kMaxStartTime, InvalidArgument,
                       "start time " + secondsText(t) + " is outside [0, " + secondsText(kMaxStartTime) + "]");
    }
    if (options.count) {
        RASTER_REQUIRE(*options.count <= 50'000'000, InvalidArgument,
                       "particle count " + std::to_string(*options.count) + " is above 50000000");
    }
    if (name == "fire") return makeFireScene(options);
    if (name == "smoke") return makeSmokeScene(options);
    if (name == "particles") return makeParticlesScene(options);
    if (name == "fog") {
        RASTER_REQUIRE(options.cubes <= 1024, InvalidArgument,
                       "cube count " + std::to_string(options.cubes) + " per side is above 1024");
        return makeFogScene(options);
    }
    const SceneEntry* entry = findRegisteredScene(name);
    if (!entry) unknownScene(name);
    std::unique_ptr<Scene> scene = entry->make(entry->name, options);
    RASTER_CHECK(scene && scene->name() == entry->name);
    return scene;
}

}  // namespace raster
