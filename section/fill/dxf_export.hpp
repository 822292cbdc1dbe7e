// DXF export of a section for mine planners' CAD, written with Debian's dxflib (libdxflib-dev
// 3.26, the writer of QCAD/LibreCAD) as AutoCAD R2000 (AC1015) ASCII DXF:
//  - one layer per unit, named after it (the body's or surface's name; characters DXF forbids
//    in layer names, <>/\":;?*|=`, become '_'; non-ASCII letters are written as DXF's \U+XXXX
//    escapes, which AutoCAD, ezdxf and LibreCAD decode), in the unit's colour (true colour,
//    group 420);
//  - every ring of a body's section (outer and holes) as a closed POLYLINE on its unit's layer,
//    and per polygon a solid HATCH (outer loop + hole loops) in the unit's colour;
//  - every surface trace as an open (or closed) POLYLINE;
//  - a TEXT label with the unit's name at each polygon's pole of inaccessibility (the point
//    farthest inside it, section/fill/labels.hpp), height `labelHeightM` or less so that it
//    fits inside (left out under a quarter of it), in colour 7 over the fill.
// Coordinates (DxfFrame): Plane writes the section's own 2D frame (u, v metres; or chainage
// and elevation for a polyline section) as DXF X, Y: the section as drawn on paper, which is
// what CAD drafting of sections uses. Projected writes 3D POLYLINEs (flag 8) in the model's
// CRS (easting, northing, elevation) so that the section sits in the mine's 3D CAD model;
// there, hatches and labels are left out: DXF hatches and text are planar entities in an
// object coordinate system that dxflib writes only for the XY plane.
// dxflib writes to a named file only: the DXF goes through a private temporary file (TMPDIR)
// that is removed before returning; a write that does not reach the end (a full disk) is an
// IoError, never a truncated answer.
// Thread-safety: pure function of its inputs (one temporary file per call).
#pragma once

#include <string>

#include "model/result.hpp"
#include "section/fill/vector_export.hpp"

namespace geoslice {

enum class DxfFrame { Plane, Projected };

struct DxfOptions {
    DxfFrame frame = DxfFrame::Plane;
    bool labels = true;
    double labelHeightM = 0.0;  // 0: 1/100 of the section's larger extent
};

// The DXF text of the section in `source` (see above). `index` supplies names and colours.
Result<std::string> toDxf(const SectionIndex& index, const VectorSource& source, const DxfOptions& options = {});

// A unit name as a DXF layer name (see above); "unnamed" for an empty one.
std::string dxfLayerName(const std::string& name);

}  // namespace geoslice
