#include "lights/environment_light.h"

#include <algorithm>
#include <cmath>

#include "core/sampling.h"

namespace penumbra {

namespace {

// The sine of the polar angle at the centre of row y: the solid angle a texel covers is
// (2 pi / width) (pi / height) sin(theta), to first order.
double rowSine(int y, int height) { return std::sin(kPi * (double(y) + 0.5) / double(height)); }

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
        const double sine = rowSine(y, image.height);
        for (int x = 0; x < image.width; ++x) {
            const Rgb texel = image.at(x, y);
            weights[size_t(y) * size_t(image.width) + size_t(x)] = float(double(texel.luminance()) * sine);
            for (int c = 0; c < 3; ++c) sum[c] += double(texel[c]) * sine;
            solidAngle += sine;
        }
    }
    data->average = solidAngle > 0.0 ? Rgb(float(sum[0] / solidAngle), float(sum[1] / solidAngle), float(sum[2] / solidAngle))
                                     : Rgb(0.0f);
    data->distribution = PiecewiseConstant2D(weights, size_t(image.width), size_t(image.height));
    light.black_ = data->distribution.empty();
    data->image = std::move(image);
    light.image_ = std::move(data);
    return light;
}

Vec2f EnvironmentLight::directionToImage(Vec3f local) {
    const float theta = std::acos(std::clamp(local.y, -1.0f, 1.0f));
    float phi = std::atan2(local.x, -local.z);
    if (phi < 0.0f) phi += 2.0f * kPi;
    const float s = std::min(phi * (0.5f * kInvPi), 1.0f - 0x1p-24f);
    const float t = std::min(theta * kInvPi, 1.0f - 0x1p-24f);
    return {s, t};
}

Vec3f EnvironmentLight::imageToDirection(Vec2f st) {
    const float phi = 2.0f * kPi * st.x, theta = kPi * st.y;
    const float sinTheta = std::sin(theta);
    return {sinTheta * std::sin(phi), std::cos(theta), -sinTheta * std::cos(phi)};
}

Rgb EnvironmentLight::lookup(Vec3f direction) const {
    const EnvironmentImage& image = image_->image;
    const Vec2f st = directionToImage(normalize(rotation_.inverse().applyVector(direction)));
    const int x = std::min(int(st.x * float(image.width)), image.width - 1);
    const int y = std::min(int(st.y * float(image.height)), image.height - 1);
    return image.at(x, y);
}

std::optional<EnvironmentSample> EnvironmentLight::sample(Vec2f u) const {
    if (!image_) return EnvironmentSample{sampleUniformSphere(u), radiance_, uniformSpherePdf()};
    float imagePdf = 0.0f;
    const Vec2f st = image_->distribution.sample(u, &imagePdf);
    const float sinTheta = std::sin(kPi * st.y);
    if (!(imagePdf > 0.0f) || !(sinTheta > 0.0f)) return std::nullopt;
    const EnvironmentImage& image = image_->image;
    const int x = std::min(int(st.x * float(image.width)), image.width - 1);
    const int y = std::min(int(st.y * float(image.height)), image.height - 1);
    // d(omega) = sin(theta) d(theta) d(phi) = 2 pi^2 sin(theta) ds dt.
    return EnvironmentSample{normalize(rotation_.applyVector(imageToDirection(st))), image.at(x, y),
                             imagePdf / (2.0f * kPi * kPi * sinTheta)};
}

float EnvironmentLight::pdf(Vec3f direction) const {
    if (!image_) return uniformSpherePdf();
    const Vec3f local = normalize(rotation_.inverse().applyVector(direction));
    const Vec2f st = directionToImage(local);
    // From the horizontal components: accurate near the poles, where 1 - y^2 cancels.
    const float sinTheta = std::sqrt(local.x * local.x + local.z * local.z);
    if (!(sinTheta > 0.0f)) return 0.0f;
    return image_->distribution.pdf(st) / (2.0f * kPi * kPi * sinTheta);
}

Rgb EnvironmentLight::average() const { return image_ ? image_->average : radiance_; }

}  // namespace penumbra
