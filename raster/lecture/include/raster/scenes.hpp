// The lecture's scenes: `fire` (a particle system burning over the occluder, animated), `sprites` (the
// lecture's three ways of drawing a sprite, animated) and `forest` (axis billboards and billboard
// clouds, alpha tested, animated), and the two
// that ../shared/bench/SCENES.md defines to the last constant, `particles` (fire billboards over an
// occluder) and `fog` (cubes on a ground plane in fog); the lecture's fog figures `fog-constant`,
// `fog-black`, `fog-coloured`, `fog-height` and part 1's `media-closed-form` (src/scene_fog.cpp,
// src/scene_media.cpp); part 1's figures by ray marching, `media-absorption`, `media-emission`,
// `media-scattering`, `media-euler` (src/scene_media_figures.cpp); the lecture's blend and depth figures,
// `blend-additive`, `blend-depthwrite`, `blend-nodepth`, `blend-unsorted`, `blend-sorted` and
// `blend-wboit` (src/scene_blending.cpp, docs/BLENDING.md); and the labs' scenes: each lab (labs/<name>/, see raster/lab.hpp) registers `<name>`, its solution
// (solutions/<name>/) `<name>@solution`.
// `raster bench`, `raster render`, the viewer and the tests all draw them through this interface.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "raster/pixel_march.hpp"

#include "raster/pipeline.hpp"
#include "raster/texture.hpp"

namespace raster {

// Where a scene is looked at from: a right-handed look-at with +y up and the scene's fixed 60° field
// of view. Each scene's SCENES.md camera is defaultCamera(name); the viewer orbits and flies from it.
struct SceneCamera {
    glm::vec3 eye, target;
};

// A volume light of the options (SceneOptions::light): a point light at `value` (world metres), or a
// directional one whose light arrives from `value`'s direction (towards the light, any length > 0).
struct SceneLight {
    bool point = false;
    glm::vec3 value{0.0f, 1.0f, 0.0f};
};

struct SceneOptions {
    uint32_t width = 1280, height = 720;
    // particles: the number of billboards; fire: the particle system's slots (maxParticles; the
    // emission rate is set so that about 3/4 of them burn at once); blend-*: the particles (200 by
    // default). Unset: the scene's own, kDefaultParticleCount (particles) or kDefaultFireCount (fire).
    std::optional<uint32_t> count;
    uint32_t cubes = 16;      // fog: cubes per side
    bool heightFog = true;    // fog: "height" (true) or "constant"
    std::string texture;      // particles, fire: a PNG to use instead of the generated fire texture
    // cloud: a volume file (.nvdb, name_XxYxZ_uint8.raw or _float32.raw) instead of the generated
    // cloud, and the generated cloud's voxels per axis (1 to 1024; unset: 256, seeded by `seed`).
    std::string volume;
    std::optional<uint32_t> voxels;
    // Animated scenes (fire): the clock's start, in seconds, simulated before the first frame, so
    // that a frame is a function of the options alone (the same bits at any thread count). Finite,
    // in [0, kMaxStartTime]. Unset: the scene's own (fire: kDefaultFireTime, burning steadily).
    // Static scenes ignore it.
    std::optional<double> time;
    // The simulation's seed, in scenes that simulate (fire: ParticleSystemDesc::seed; the labs that
    // simulate); the lecture's particles and fog are fixed functions of the count and have none.
    uint32_t seed = 0;
    // The vertical field of view in degrees, in (0, 179]; unset, SCENES.md's 60° (every scene's
    // projection is sceneProjection(options)). Wide angles show how sprites differ near the image's
    // edges (the `sprites` scene, docs/PARTICLES.md).
    std::optional<float> fovDegrees;
    // Overrides the scene's camera. Unset, the scene is exactly SCENES.md's (what `raster bench`
    // measures); set to defaultCamera(name), it renders the same image bit for bit.
    std::optional<SceneCamera> camera;
    // The fog scenes (fog, fog-*, media-closed-form) and the fog lab: the medium, replacing the scene's
    // own. fogSigma: the extinction σ, per metre, RGB; fogSource: the source term q, radiance per metre,
    // RGB (the fog's colour seen to infinity is q/σ); fogFalloff: the height fog's falloff B, per metre,
    // its density e^{−B·y} (the lecture's σ(y) = σ0·e^{b·y} with b = −B). Each component finite and
    // ≥ 0 (fogValueProblem), and q/σ a finite float where σ > 0; else makeScene's Error names it.
    // media-absorption takes fogSigma as its absorption and media-emission fogSource as its emission,
    // per unit metaball density.
    std::optional<glm::vec3> fogSigma, fogSource;
    std::optional<float> fogFalloff;
    // The scenes that march a volume light (volumeLightScenes(): media, cloud, cloud-point): a light
    // in place of the scene's own (a point light or a directional one, SceneLight), and its strength,
    // RGB: a point light's radiant intensity I (per steradian: irradiance I/r² at r metres), a
    // directional one's irradiance E. Unset strength: a light of the scene's own light's kind keeps
    // its strength; one of the other kind gives the medium's centre the irradiance the scene's own
    // gives it. Numbers finite, the intensity ≥ 0, a direction not 0; another scene refuses them
    // (makeScene's Error names each).
    std::optional<SceneLight> light;
    std::optional<glm::vec3> lightIntensity;
};

// What is wrong with one number of a light's position or direction, "" when nothing: a finite float.
// "nan is not a number", "inf is infinite", "1e+39 is too large for a float".
std::string finiteValueProblem(double value);

// What is wrong with a light (SceneOptions::light), "" when nothing: a number as finiteValueProblem
// says, or "the direction (0, 0, 0) has no length" (a directional light's, normalised to NaN).
std::string sceneLightProblem(const SceneLight& light);

// The scenes that take SceneOptions::light and lightIntensity.
const std::vector<std::string_view>& volumeLightScenes();

// What is wrong with one component of a fog parameter (σ, q or the falloff B), "" when nothing: each is
// a finite float ≥ 0. "nan is not a number", "inf is infinite", "1e+39 is too large for a float",
// "-1 is negative" (the value as %g prints it).
std::string fogValueProblem(double value);

constexpr uint32_t kDefaultParticleCount = 10000;
constexpr uint32_t kDefaultFireCount = 4000;
constexpr double kDefaultFireTime = 3.0;  // seconds after the fire is lit
constexpr double kMaxStartTime = 600.0;   // seconds: 36 000 steps of 1/60 s to simulate first

// A scene draws frames; an animated one also has a clock.
//
// Time, for animated scenes: the clock starts at SceneOptions::time and only advance() moves it;
// render() draws the state at the clock's time without changing it. The state is that of a whole
// number of fixed simulation steps (the fire's: ParticleSystemDesc::timeStep = 1/60 s), the steps
// that fit in the clock's time, never a fraction of one: ParticleSystem::advance's rule, time not yet
// simulated carried over, a step run once 1 − 10⁻⁴ of it has accumulated, none ever dropped. So
// the frame rate does not change the motion: advance(0.5) twice and a start at 1.0 are both the
// same 60 steps, and a frame is a function of (options, the sum of the advances) — bit for bit, at
// any thread count (the simulation is deterministic for a seed). Static scenes keep time 0 and
// ignore advance() (after checking its argument).
class Scene {
public:
    virtual ~Scene() = default;
    virtual std::string_view name() const = 0;
    // Clears the targets and draws one frame, at the scene's current time.
    virtual void render(Context& context, RenderTarget& color, DepthTarget& depth) = 0;

    virtual bool animated() const { return false; }
    // A scene whose pixels march a ray through a medium: pixel (x, y)'s march in a width × height
    // target, sample by sample, as its pixel shader runs it (`raster trace --pixel`, the viewer's march
    // plot); nullopt for the other scenes.
    virtual std::optional<PixelMarch> pixelMarch(uint32_t /*x*/, uint32_t /*y*/, uint32_t /*width*/,
                                                 uint32_t /*height*/) const {
        return std::nullopt;
    }
    // The clock, in seconds: the start time plus every advance so far (0 for a static scene).
    virtual double time() const { return 0.0; }
    // Moves the clock on by `seconds` (finite and ≥ 0, else Error(InvalidArgument) naming it) and
    // simulates the whole steps that now fit. Takes as long as the steps do: one frame's worth
    // (1/60 s, one step) is cheap, a minute of time is 3600 steps.
    void advance(double seconds);

protected:
    virtual void advanceBy(double /*seconds*/) {}  // seconds already checked
};

// Throws Error(InvalidArgument) for an unknown scene name or an option out of range.
std::unique_ptr<Scene> makeScene(std::string_view name, const SceneOptions& options);
// The lecture's scenes first (fire, sprites, forest, particles, fog, the blend-* figures), then the
// registered ones in name order.
std::vector<std::string> sceneNames();
// SCENES.md's camera of a scene, or a registered scene's. Throws Error(InvalidArgument) for an
// unknown scene name.
SceneCamera defaultCamera(std::string_view name);

// ---- Registered scenes (the labs) -------------------------------------------------------------------
// What makeScene needs to build a scene it does not know itself. `make` gets options already checked
// for size and camera, and must return a scene whose name() is `name`.
struct SceneEntry {
    std::string name;
    std::string title;  // one line for listings, e.g. "Lab: billboards and particles (lecture 11, part 3)"
    SceneCamera camera;
    std::unique_ptr<Scene> (*make)(const std::string& name, const SceneOptions& options) = nullptr;
};
// Adds a scene; usually called before main by RASTER_LAB (raster/lab.hpp). Throws
// Error(InvalidArgument) for an empty name, a name already taken, one with characters other than
// [a-z0-9_-@] or a null `make`.
void registerScene(SceneEntry entry);
// The registered entry of `name`, or nullptr (the lecture's own scenes are not registered).
const SceneEntry* findRegisteredScene(std::string_view name);
// The scene a lab's picture is compared with: "<name>@solution" when that is registered, else "".
std::string solutionSceneOf(std::string_view name);

// SCENES.md's camera conventions, for every scene: glm::perspectiveRH_ZO with a 60° vertical field of
// view (or the options' fovDegrees), the options' aspect, near 0.1 and far 100; glm::lookAtRH from eye to target with +y up.
glm::mat4 sceneProjection(const SceneOptions& options);
glm::mat4 sceneView(const SceneCamera& camera);

// Clears colour to (0,0,0,1) and depth to 1, binds both, sets the whole-target viewport, no culling and
// the library's coverage rule (no coverage test): how every scene's frame begins (SCENES.md's conventions).
void beginSceneFrame(Context& context, RenderTarget& color, DepthTarget& depth);

// SCENES.md's particle scene as data, for the `particles` scene, the lab that rebuilds it and the
// `fire` scene (its occluder): the occluder (two triangles) and `count` particles (the options'
// count, or kDefaultParticleCount), both POSITION R32G32B32_FLOAT in `layout`.
struct ParticleSceneData {
    explicit ParticleSceneData(const SceneOptions& options);
    // Draw 1 of SCENES.md: the occluder, opaque (depth test Less and write, no blending), with
    // this input layout bound; it leaves those states set.
    void drawOccluder(Context& context) const;
    glm::mat4 viewProj;       // P·V for the options' camera (SCENES.md's when unset)
    glm::vec2 billboardSize;  // h·P[0][0], h·P[1][1] for the sprites' world half-size h = 0.08
    glm::vec4 occluderColor;  // (89, 140, 64, 255) / 255
    Texture2D texture;        // makeFireTexture(), or the options' PNG
    VertexBuffer occluder, particles;
    InputLayout layout;
    uint32_t count;
};

// The fog figures' world (fog-constant, fog-black, fog-coloured, fog-height, media-closed-form and the fog
// lab), SCENES.md's fog scene made recognisable: its ground (x in [−40, 40], z in [−80, 8], y = 0) as a
// checkerboard of 2 m tiles and its lattice of `cubes` × `cubes` cubes (half-extent 0.5, centres
// ((ix − (cubes − 1)/2)·4, 0.5, −4·iz − 2)) in four colours. One vertex buffer of lit vertices, POSITION
// and NORMAL R32G32B32_FLOAT each (`layout`, 24 bytes a vertex, triangle lists, flat normals), drawn part
// by part with each part's albedo; and the sky, one full-screen triangle of POSITION R32G32_FLOAT
// (`skyLayout`, clip-space x and y) for a pixel shader that looks through the medium to s = ∞.
struct FogWorldData {
    explicit FogWorldData(uint32_t cubes);
    struct Part {
        uint32_t first, count;  // vertices of `lit`
        glm::vec3 albedo;
    };
    std::vector<Part> parts;  // the light tiles, the dark tiles, then the cubes colour by colour
    VertexBuffer lit, sky;
    InputLayout layout, skyLayout;
};

// The rasterizer lab's adversarial triangles (labs/rasterizer/README.md), one TriangleList of
// `vertexCount` vertices, each POSITION (clip space, w = 1) and COLOR R32G32B32A32_FLOAT, drawn with
// additive blending so that a pixel covered twice shows brighter and one covered never stays dark:
//   - two huge triangles sharing a diagonal, reaching past the guard band, behind everything;
//   - a fan of 8 + 4·(count % 5) triangles about a pixel centre, spokes ending on pixel centres,
//     windings alternating;
//   - a lattice of cells of 5 + count % 4 pixels with corners on pixel centres, each cut by a
//     diagonal into two triangles, windings alternating;
//   - slivers: 40 wedges under a pixel wide from one apex, and strips half a pixel high whose top
//     edges run along rows of pixel centres;
//   - `count` small triangles (at most 50 000) at positions off the 1/256 grid, seeded by count.
// Positions are placed in pixels and mapped by the camera: a rotation about the image's centre by
// the eye's azimuth about the target and a zoom by 1 / |eye − target| (the default camera, eye
// (0, 0, 1) and target the origin, maps nothing: every vertex meant for a pixel centre snaps there).
struct CoverageSceneData {
    struct Vertex {
        glm::vec4 position, color;
    };
    explicit CoverageSceneData(const SceneOptions& options);
    // Binds the layout, the buffer and the triangle list, additive blending and no depth test.
    void bind(Context& context) const;
    VertexBuffer triangles;
    InputLayout layout;
    uint32_t vertexCount = 0;
};

// The fire texture of SCENES.md: 64×64 RGBA8, texel (i, j): u = (i+½)/64, v = (j+½)/64,
// r = 2·|(u,v) − ½|, s = clamp(1 − r, 0, 1)², RGBA = round(255·(1, 0.25 + 0.55s, 0.05 + 0.15s, 0.25s)).
Texture2D makeFireTexture();

// Particle i of SCENES.md's R3 low-discrepancy sequence (computed in double, rounded to float).
glm::vec3 particlePosition(uint32_t i);

}  // namespace raster
