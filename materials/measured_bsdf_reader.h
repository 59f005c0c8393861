// Reading a measured BRDF of the RGL material database (Dupuy and Jakob 2018): a tensor file
// (core/tensor_file.h) with the fields pbrt-v4 and Mitsuba read:
//   description (uint8 text), jacobian (uint8 [1]), theta_i, phi_i (float32: the viewer's elevations
//   and azimuths, radians, increasing), ndf, sigma (float32 [rows, columns]), vndf, luminance
//   (float32 [phi_i, theta_i, rows, columns]), and the reflectance either as spectra (float32
//   [phi_i, theta_i, wavelengths, rows, columns] with wavelengths (float32, nm, increasing): the
//   database's spectral files, integrated here to RGB against the CIE 1931 observer as a reflectance
//   under D65) or as rgb (float32 [phi_i, theta_i, 3, rows, columns]: its RGB files).
// Everything is checked before a table is built: shapes that agree, grids of at least 2 x 2, finite
// values in plausible ranges, densities (vndf, luminance) non-negative and not zero everywhere. Any
// other file is an InputError naming the file and what was expected.
#pragma once

#include <filesystem>
#include <memory>
#include <string>
#include <string_view>

#include "materials/measured_bsdf.h"

namespace penumbra {

// Throws InputError naming `path` (missing, not a regular file, larger than
// limits::kMaxMeasuredBsdfFileBytes, or not a measured BRDF).
std::shared_ptr<const MeasuredBrdfTables> readMeasuredBsdf(const std::filesystem::path& path);
// The same from the file's bytes; `fileName` names it in errors.
std::shared_ptr<const MeasuredBrdfTables> parseMeasuredBsdf(std::string_view bytes,
                                                            const std::string& fileName);

}  // namespace penumbra
