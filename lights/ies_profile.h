// A luminaire's intensity distribution read from an IES photometric file (IESNA LM-63: the
// 1986 layout with no identifier line, "IESNA91" for LM-63-1991, "IESNA:LM-63-1995",
// "IESNA:LM-63-2002" and "IES:LM-63-2019"), for the goniometric light.
//
// Only type C photometry (the vertical axis through the luminaire, LM-63's photometric type 1)
// is read; types A and B are refused. The table's symmetries are unfolded at load, so that a
// profile always covers every horizontal angle:
// - horizontal angles {0}: rotationally symmetric;
// - 0..90: symmetric in each quadrant (about the 0-180 and the 90-270 planes);
// - 0..180: bilaterally symmetric about the 0-180 plane;
// - 90..270: bilaterally symmetric about the 90-270 plane (LM-63-2002);
// - 0..L with 180 < L <= 360: no symmetry; between L and 360 the intensity is interpolated
//   between the last angle and 0 (360).
// Vertical angles run from 0 (nadir) or 90 to at most 180 (zenith); directions outside the
// file's vertical range emit nothing.
//
// Frame: a direction d in the luminaire's local frame has the vertical angle
// theta = angle(d, +z), so +z is the nadir (vertical angle 0: straight down the luminaire's
// axis) and -z the zenith, and the horizontal angle phi = atan2(d.y, d.x), measured from +x
// (LM-63's 0 plane, along the luminaire's length) towards +y (its 90 plane).
// Handedness: type C horizontal angles turn counterclockwise seen from above the luminaire (plan
// view). Seen from above, looking along +z, the turn from +x towards +y is clockwise, so a
// right-handed frame with +z down shows a luminaire's distribution mirrored about its 0-180 plane:
// a light placing it with a rotation negates y (or phi) where it matters. It does not for
// rotationally, quadrant and 0..180 bilaterally symmetric files, the great majority.
//
// Between the table's angles the intensity is bilinear in (theta, phi), in degrees as the file
// gives them; at the table's angles it is exactly the file's value (times the multipliers).
#pragma once

#include <filesystem>
#include <string_view>
#include <vector>

#include "core/vec.h"

namespace penumbra {

enum class IesVersion { Lm63_1986, Lm63_1991, Lm63_1995, Lm63_2002, Lm63_2019 };

class IesProfile {
public:
    IesProfile() = default;  // dark: emits nothing

    // Candela towards `localDirection` (any length; the frame above); 0 for a zero or non-finite
    // direction.
    float intensity(Vec3f localDirection) const;
    // Candela at vertical angle `verticalDegrees` (0 = nadir) and horizontal angle
    // `horizontalDegrees` (any value; taken modulo 360); 0 outside the vertical range and for
    // non-finite angles.
    float candelaAt(double verticalDegrees, double horizontalDegrees) const;

    // The integral of intensity() over the sphere: lumens where the file's values are candela.
    // Exact (in double precision) for the bilinear interpolant: over a cell of the table the
    // integral of f(theta, phi) sin(theta) has a closed form (ies_profile.cpp).
    double totalFlux() const { return totalFlux_; }
    // The largest intensity in any direction (the interpolant's maximum is at a table angle).
    float maxCandela() const { return maxCandela_; }

    IesVersion version() const { return version_; }
    int lampCount() const { return lampCount_; }
    // The rated lumens of each lamp, or -1 for absolute photometry (as LM-63 writes it).
    double lumensPerLamp() const { return lumensPerLamp_; }
    bool absolutePhotometry() const { return lumensPerLamp_ < 0; }

    // The table as unfolded: vertical angles ascending from 0 or 90; horizontal angles ascending
    // over one whole turn (the last is the first plus 360, with the first's values); value(v, h)
    // is the candela at vertical angle v and horizontal angle h, multipliers applied.
    const std::vector<double>& verticalAngles() const { return vertical_; }
    const std::vector<double>& horizontalAngles() const { return horizontal_; }
    float value(size_t v, size_t h) const { return candela_[h * vertical_.size() + v]; }

private:
    friend IesProfile readIesProfileText(std::string_view text, std::string_view nameForErrors);

    IesVersion version_ = IesVersion::Lm63_2002;
    int lampCount_ = 1;
    double lumensPerLamp_ = -1;
    std::vector<double> vertical_, horizontal_;  // degrees
    std::vector<float> candela_;                 // horizontal-major, as the file lists them
    double totalFlux_ = 0;
    float maxCandela_ = 0;
};

// Reads an IES file; throws InputError naming the file, and for a malformed one the line and
// what was expected there. Files are at most limits::kMaxIesFileBytes.
IesProfile readIesProfile(const std::filesystem::path& path);
// The same from the file's text; `nameForErrors` stands for the file in messages.
IesProfile readIesProfileText(std::string_view text, std::string_view nameForErrors);

}  // namespace penumbra
