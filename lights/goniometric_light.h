// A goniometric light (pbrt-v4's GoniometricLight): a point light whose intensity varies with
// direction as a measured photometric profile gives it: an IES LM-63 file (lights/ies_profile.h),
// the format lighting catalogues ship, or an equal-area image as pbrt-v4 takes it
// (lights/intensity_image.h).
#pragma once

#include <memory>
#include <variant>

#include "core/frame.h"
#include "core/rgb.h"
#include "core/vec.h"
#include "lights/ies_profile.h"
#include "lights/intensity_image.h"
#include "lights/point_light.h"

namespace penumbra {

// The profiles a goniometric light takes, over the same local directions: +z the nadir (vertical
// angle 0; an image's pole), x horizontal angle 0, y horizontal angle 90 degrees.
using IntensityProfile = std::variant<IesProfile, IntensityImage>;

inline float profileIntensity(const IntensityProfile& profile, Vec3f local) {
    return std::visit([local](const auto& p) { return p.intensity(local); }, profile);
}
inline double profileFlux(const IntensityProfile& profile) {
    return std::visit([](const auto& p) { return p.totalFlux(); }, profile);
}

struct GoniometricLight {
    Vec3f position;
    // The profile's axes in the world (profileFrame): n its nadir (vertical angle 0, the
    // luminaire's axis), s its horizontal angle 0, t its horizontal angle 90 degrees.
    Frame frame;
    Rgb scale{1.0f};  // radiant intensity per candela of the profile, W/sr per channel
    std::shared_ptr<const IntensityProfile> profile;

    // The profile's frame for a luminaire whose axis points along `nadir` and whose horizontal
    // angle 0 lies towards `front` (both non-zero, not parallel). Type C horizontal angles turn
    // counterclockwise seen from above the luminaire (LM-63), so angle 90 is front x nadir: the
    // frame is left-handed, which its dot products do not mind.
    static Frame profileFrame(Vec3f nadir, Vec3f front) {
        const Vec3f n = normalize(nadir);
        const Vec3f s = normalize(front - n * dot(front, n));
        return {s, cross(s, n), n};
    }

    // The radiant intensity towards the unit world direction `w` (away from the light).
    Rgb intensity(Vec3f w) const { return scale * profileIntensity(*profile, frame.toLocal(w)); }

    static constexpr bool kIsDelta = true, kIsInfinite = false;

    static constexpr bool kPointIndependentOfReference = true;
    // The profile's flux (its intensity integrated over the sphere) times the scale.
    double power(double /*sceneRadius*/) const { return profileFlux(*profile) * double(scale.luminance()); }
    LightBounds bounds(float power) const {
        LightBounds b;
        b.phi = power;
        b.center = position;
        return b;  // every direction: the profile may light any of them
    }
    bool sample(Vec3f reference, Vec2f /*u*/, LightSample& ls) const {
        if (!samplePointSource(position, scale, reference, ls)) return false;
        ls.radiance *= profileIntensity(*profile, frame.toLocal(-ls.direction));
        return true;
    }
    float pdf(Vec3f /*reference*/, Vec3f /*point*/) const { return 0.0f; }
};

}  // namespace penumbra
