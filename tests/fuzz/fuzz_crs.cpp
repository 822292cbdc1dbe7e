// libFuzzer target for Crs::parse (CRS texts from sidecars, <stem>.crs files, --crs, GOCAD
// and Geo3DML declarations): any bytes must give a CRS or an error, never a crash or a
// hang; a CRS it gives must survive parse(id()) and a conversion attempt.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "model/crs/crs.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size > 4096) return 0;  // WKT of real CRSs is a few KiB; longer inputs only slow PROJ down
    std::string_view text(reinterpret_cast<const char*>(data), size);
    auto crs = geoslice::Crs::parse(text);
    if (!crs.ok()) return 0;
    auto again = geoslice::Crs::parse(crs->id());
    if (!again.ok() || !(again.value() == crs.value())) __builtin_trap();
    if (crs->isProjected()) (void)crs->toLonLat(1000.0, 2000.0);
    (void)crs->checkModelCrs();
    return 0;
}
