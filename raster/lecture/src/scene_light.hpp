// The volume light of a scene that marches one (media, cloud, cloud-point), the options' --light and
// --light-intensity (SceneOptions::light, lightIntensity) put in place of the scene's own. Internal to
// the library.
#pragma once

#include <glm/glm.hpp>
#include <string>

#include "raster/check.hpp"
#include "raster/media/volume_light.hpp"
#include "raster/scenes.hpp"

namespace raster {

// The scene's light `own` (world metres) with the options' light and intensity put in its place: its
// ambient term, g and albedo kept. Where the options give no intensity, a light of own's kind keeps
// own's (E or I), and one of the other kind is given the irradiance own gives the medium's `centre`
// (world metres): a point light at distance r from it I = E·r², a directional one E = I/r² (a point
// light at the centre itself has no such I: Error(InvalidArgument), asking for an intensity).
inline media::VolumeLight optionsLight(const media::VolumeLight& own, const SceneOptions& o, const glm::vec3& centre) {
    media::VolumeLight light = own;
    if (o.light) {
        const bool own_point = own.kind == media::LightKind::point;
        const glm::vec3 at_centre = own_point ? media::lightAt(own, centre).irradiance : own.sun;
        if (o.light->point) {
            const glm::vec3 v = o.light->value - centre;
            const float r2 = glm::dot(v, v);
            RASTER_REQUIRE(own_point || r2 > 0.0f || o.lightIntensity, InvalidArgument,
                           "light: a point light at the medium's centre needs an intensity (--light-intensity)");
            light.kind = media::LightKind::point;
            light.position = o.light->value;
            if (!own_point) light.intensity = at_centre * r2;
        } else {
            light.kind = media::LightKind::directional;
            light.toLight = glm::normalize(o.light->value);
            if (own_point) light.sun = at_centre;
        }
    }
    if (o.lightIntensity) (light.kind == media::LightKind::point ? light.intensity : light.sun) = *o.lightIntensity;
    return light;
}

}  // namespace raster
