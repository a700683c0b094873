// bmWindowedVolume.h - a CT stored as an 8-bit display window, as some hospitals export scans
// (a lung-screening CT, a teaching file): value = round(255 (HU - (centre - width / 2)) / width),
// clamped to 0..255, in an unsigned-char NRRD or MetaImage with the CT's geometry. What reads such
// a file gets no HU: the import refuses it until told how to read it (raw values or an HU mapping,
// bmIntensityMapping.h). Used to make test scans that carry that property.
#pragma once

#include "bmCTImage.h"

#include <array>
#include <string>

namespace bm {

/// The 8-bit value of `hu` in the window (centre, width), HU; width > 0.
unsigned char WindowedValue(float hu, double centreHU, double widthHU);

/// The HU mapping that reads such a file back: {slope, intercept}, HU = slope x value + intercept.
std::array<double, 2> WindowToHUMapping(double centreHU, double widthHU);

/// Save `ct` windowed to 8 bits at `path` (.nrrd or .mha, compressed; atomic: a temporary, then a
/// rename). Throws std::invalid_argument for a width <= 0 or another extension, std::runtime_error
/// when the file cannot be written.
void SaveWindowedVolume(const CTImage& ct, double centreHU, double widthHU,
                        const std::string& path);

} // namespace bm
