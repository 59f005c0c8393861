#include "lights/environment_light.h"

#include <algorithm>
#include <cmath>

#include "core/equal_area.h"
#include "core/sampling.h"

namespace penumbra {

namespace {

// The solid angle a texel of row y covers, up to a factor common to all texels: sin(theta) at the
// row's centre for the equirectangular map (to first order), 1 for the equal-area one.
double rowSolidAngle(int y, int height, EnvironmentMapping mapping) {
    if (mapping == EnvironmentMapping::EqualArea) return 1.0;
    return std::sin(kPi * (double(y) + 0.5) / double(height));
}

}  // namespace

EnvironmentLight EnvironmentLight::constant(Rgb radiance) {
    EnvironmentLight light;
    light.radiance_ = radiance;
    light.black_ = radiance.isBlack();
    return light;
}

EnvironmentLight EnvironmentLight::fromImage(EnvironmentImage image, Rgb scale, const Transform& rotation) {
    EnvironmentLight light;
    light.radiance_ = scale;
    light.rotation_ = rotation;
    auto data = std::make_shared<ImageData>();
    for (Rgb& texel : image.texels)
        for (int c = 0; c < 3; ++c) {
            float& value = c == 0 ? texel.r : c == 1 ? texel.g : texel.b;
            value = (value > 0.0f && std::isfinite(value)) ? value * scale[c] : 0.0f;
        }
    std::vector<float> weights(image.texels.size());
    double sum[3] = {0.0, 0.0, 0.0}, solidAngle = 0.0;
    for (int y = 0; y < image.height; ++y) {
        const double texelSolidAngle = rowSolidAngle(y, image.height, image.mapping);
        for (int x = 0; x < image.width; ++x) {
            const Rgb texel = image.at(x, y);
            weights[size_t(y) * size_t(image.width) + size_t(x)] =
                float(double(texel.luminance()) * texelSolidAngle);
            for (int c = 0; c < 3; ++c) sum[c] += double(texel[c]) * texelSolidAngle;
            solidAngle += texelSolidAngle;
        }
    }
    data->average = solidAngle > 0.0 ? Rgb(float(sum[0] / solidAngle), float(sum[1] / solidAngle),
                                           float(sum[2] / solidAngle))
                                     : Rgb(0.0f);
    data->distribution = PiecewiseConstant2D(weights, size_t(image.width), size_t(image.height));
    light.black_ = data->distribution.empty();
    data->image = std::move(image);
    light.image_ = std::move(data);
    return light;
}

Vec2f EnvironmentLight::directionToImage(Vec3f local, EnvironmentMapping mapping) {
    constexpr float kBelowOne = 1.0f - 0x1p-24f;
    if (mapping == EnvironmentMapping::EqualArea) {
        const Vec2f st = equalAreaSphereToSquare({local.x, -local.z, local.y});
        return {std::clamp(st.x, 0.0f, kBelowOne), std::clamp(st.y, 0.0f, kBelowOne)};
    }
    const float theta = std::acos(std::clamp(local.y, -1.0f, 1.0f));
    float phi = std::atan2(local.x, -local.z);
    if (phi < 0.0f) phi += 2.0f * kPi;
    const float s = std::min(phi * (0.5f * kInvPi), kBelowOne);
    const float t = std::min(theta * kInvPi, kBelowOne);
    return {s, t};
}

Vec3f EnvironmentLight::imageToDirection(Vec2f st, EnvironmentMapping mapping) {
    if (mapping == EnvironmentMapping::EqualArea) {
        const Vec3f abc = equalAreaSquareToSphere(st);
        return {abc.x, abc.z, -abc.y};
    }
    const float phi = 2.0f * kPi * st.x, theta = kPi * st.y;
    const float sinTheta = std::sin(theta);
    return {sinTheta * std::sin(phi), std::cos(theta), -sinTheta * std::cos(phi)};
}

Rgb EnvironmentLight::lookup(Vec3f direction) const {
    const EnvironmentImage& image = image_->image;
    const Vec2f st = directionToImage(normalize(rotation_.inverse().applyVector(direction)), image.mapping);
    const int x = std::min(int(st.x * float(image.width)), image.width - 1);
    const int y = std::min(int(st.y * float(image.height)), image.height - 1);
    return image.at(x, y);
}

std::optional<EnvironmentSample> EnvironmentLight::sample(Vec2f u) const {
    if (!image_) return EnvironmentSample{sampleUniformSphere(u), radiance_, uniformSpherePdf()};
    float imagePdf = 0.0f;
    const Vec2f st = image_->distribution.sample(u, &imagePdf);
    const EnvironmentImage& image = image_->image;
    // d omega / ds dt; for the equirectangular map 2 pi^2 sin(theta), with theta from t.
    const float jacobian =
        image.mapping == EnvironmentMapping::EqualArea ? 4.0f * kPi : 2.0f * kPi * kPi * std::sin(kPi * st.y);
    if (!(imagePdf > 0.0f) || !(jacobian > 0.0f)) return std::nullopt;
    const Vec3f local = imageToDirection(st, image.mapping);
    const int x = std::min(int(st.x * float(image.width)), image.width - 1);
    const int y = std::min(int(st.y * float(image.height)), image.height - 1);
    return EnvironmentSample{normalize(rotation_.applyVector(local)), image.at(x, y), imagePdf / jacobian};
}

float EnvironmentLight::pdf(Vec3f direction) const {
    if (!image_) return uniformSpherePdf();
    const EnvironmentMapping mapping = image_->image.mapping;
    const Vec3f local = normalize(rotation_.inverse().applyVector(direction));
    // d omega / ds dt; for the equirectangular map 2 pi^2 sin(theta), sin(theta) from the
    // horizontal components: accurate near the poles, where 1 - y^2 cancels.
    const float jacobian = mapping == EnvironmentMapping::EqualArea
                               ? 4.0f * kPi
                               : 2.0f * kPi * kPi * std::sqrt(local.x * local.x + local.z * local.z);
    if (!(jacobian > 0.0f)) return 0.0f;
    return image_->distribution.pdf(directionToImage(local, mapping)) / jacobian;
}

Rgb EnvironmentLight::average() const { return image_ ? image_->average : radiance_; }

}  // namespace penumbra
