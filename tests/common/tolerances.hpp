// Tolerances that several test files share because their reason is the same (every other
// tolerance is named in its own file, next to its reason). Units in each name's comment.
#pragma once

namespace geoslice::test {

// Metres: world points at Gauss-Kruger eastings with the zone prefix (3.5e7 m), where a
// double step is 7.5e-9 m and a pixel -> plane -> world chain takes a few dozen operations;
// far below any pixel or frame error.
constexpr double kGkWorldTolM = 1e-6;

// Relative: the volume a closed boundary shell encloses (its triangles' divergence sum)
// against the sum of the volumes of the cells it was built from: the same quantity summed
// in another order over hundreds to thousands of terms.
constexpr double kShellVsCellSumRelTol = 1e-9;

// Degrees: our coordinates against cs2cs where both run the same PROJ operation (cs2cs prints
// 10 decimals): 1e-9 degrees is 0.1 mm on the ground.
constexpr double kSamePipelineDeg = 1e-9;

}  // namespace geoslice::test
