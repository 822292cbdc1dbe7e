#pragma once
// SGrids (model/model.hpp Grid, type "SGrid") as the tests build them in memory.
#include <cstddef>
#include <optional>

#include "model/model.hpp"

namespace geoslice::test {

// An SGrid of n0 x n1 x n2 cells with points at(i, j, k) and cell property grade(i, j, k).
template <class At, class Grade>
Grid sgridOf(int n0, int n1, int n2, At at, Grade grade) {
    Grid g;
    g.type = "SGrid";
    g.name = "sg";
    g.dims[0] = std::size_t(n0 + 1);
    g.dims[1] = std::size_t(n1 + 1);
    g.dims[2] = std::size_t(n2 + 1);
    g.cellCentred = true;
    for (int k = 0; k <= n2; ++k)
        for (int j = 0; j <= n1; ++j)
            for (int i = 0; i <= n0; ++i) g.points.push_back(at(i, j, k));
    GridProperty p{"grade", "g/t", std::nullopt, {}};
    for (int k = 0; k < n2; ++k)
        for (int j = 0; j < n1; ++j)
            for (int i = 0; i < n0; ++i) p.values.push_back(float(grade(i, j, k)));
    g.properties.push_back(std::move(p));
    return g;
}

}  // namespace geoslice::test
