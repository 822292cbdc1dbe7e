// A bounding-volume hierarchy over the axis-aligned bounds of a block model's cells
// (model/blocks/block_model.hpp, curvilinear cells): which cells may hold a point, which cells may
// meet a box or a plane. Median splits along the longest axis of the cells' centres, leaves of
// at most kLeafCells cells, nodes in one array (children after their parent). Bounds are
// world metres and inclusive (a point on a cell's bounds is reported), so callers decide
// containment with their exact test. Immutable once built: any thread may query.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "model/model.hpp"

namespace geoslice {

class CellLocator {
public:
    static constexpr std::size_t kLeafCells = 4;

    // `bounds[c]` is cell c's bounds; cells with invalid bounds are left out.
    explicit CellLocator(const std::vector<Aabb>& bounds);

    // Calls visit(cell) for every cell whose bounds satisfy `meets`, in a fixed order;
    // `meets` is also asked of every node's bounds: it must hold for a box whenever it holds
    // for a box inside it (a point in it, a plane crossing it, a box meeting it).
    template <class Meets, class Visit>
    void cellsMeeting(const Meets& meets, const Visit& visit) const {
        if (order_.empty()) return;
        std::uint32_t stack[128];  // median splits: depth <= log2(cells) + 1
        int top = 0;
        stack[top++] = 0;
        while (top > 0) {
            const Node& n = nodes_[stack[--top]];
            if (!meets(n.box)) continue;
            if (n.count > 0) {
                for (std::uint32_t k = n.first; k < n.first + n.count; ++k)
                    if (meets(cellBounds_[order_[k]])) visit(std::size_t(order_[k]));
                continue;
            }
            stack[top++] = n.right;
            stack[top++] = n.first;
        }
    }
    // Every cell whose bounds hold `p` (bounds inclusive).
    template <class Visit>
    void cellsAt(const glm::dvec3& p, const Visit& visit) const {
        cellsMeeting(
            [&p](const Aabb& b) {
                return p.x >= b.min.x && p.x <= b.max.x && p.y >= b.min.y && p.y <= b.max.y && p.z >= b.min.z &&
                       p.z <= b.max.z;
            },
            visit);
    }

    const Aabb& bounds() const;

private:
    struct Node {
        Aabb box;
        std::uint32_t first = 0, count = 0;  // leaf (count > 0): cells order_[first .. first + count)
        std::uint32_t right = 0;             // inner node (count = 0): children `first` and `right`
    };
    std::vector<Node> nodes_;
    std::vector<std::uint32_t> order_;
    std::vector<Aabb> cellBounds_;
};

}  // namespace geoslice
