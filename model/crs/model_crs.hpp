// A model's CRS from its declarations, weakest first:
//   1. the model file's own (glTF extras, Geo3DML, GOCAD GOCAD_ORIGINAL_COORDINATE_SYSTEM);
//   2. the JSON attributes sidecar's top-level "crs" (`<stem>.attributes.json`), for formats
//      that carry none (OBJ): used when the file declares none; when both declare and
//      differ, the file's is kept and a warning says so;
//   3. a `<stem>.crs` file beside the model (one CRS text: "EPSG:2056", a name, WKT), and
//   4. `--crs` on the command line: explicit overrides, which replace the file's CRS (a
//      warning names both when they differ).
// "local" is a valid declaration at every level (and so removes a CRS). The result must
// be usable for a model (Crs::checkModelCrs: metres). Where each came from and any
// warning go to model.notes ("crs_source", "crs_warning"); loadModel prints the warning on
// stderr and the server logs it.
#pragma once

#include <string>
#include <string_view>

#include "model/model.hpp"
#include "model/result.hpp"

namespace geoslice {

enum class CrsDeclaration { Sidecar, CrsFile, Override };

// Applies one declaration (levels 2-4 above); `origin` names it in messages and notes
// ("rock.attributes.json", "rock.crs", "--crs"). Errors: text PROJ cannot read, a CRS a
// model cannot use.
Status declareModelCrs(Model& model, std::string_view text, CrsDeclaration level, const std::string& origin);

}  // namespace geoslice
