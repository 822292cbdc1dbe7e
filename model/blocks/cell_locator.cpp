#include "model/blocks/cell_locator.hpp"

#include <algorithm>

namespace geoslice {

CellLocator::CellLocator(const std::vector<Aabb>& bounds) : cellBounds_(bounds) {
    for (std::size_t c = 0; c < bounds.size(); ++c)
        if (bounds[c].valid()) order_.push_back(std::uint32_t(c));
    nodes_.reserve(2 * (order_.size() / kLeafCells + 1));
    // Iterative build: (node index, first, count) to split.
    struct Job {
        std::uint32_t node, first, count;
    };
    std::vector<Job> stack;
    nodes_.push_back({});
    stack.push_back({0, 0, std::uint32_t(order_.size())});
    while (!stack.empty()) {
        const Job job = stack.back();
        stack.pop_back();
        Aabb box, centres;
        for (std::uint32_t k = job.first; k < job.first + job.count; ++k) {
            box.extend(cellBounds_[order_[k]]);
            centres.extend(cellBounds_[order_[k]].centre());
        }
        nodes_[job.node].box = box;
        if (job.count <= kLeafCells) {
            nodes_[job.node].first = job.first;
            nodes_[job.node].count = job.count;
            continue;
        }
        const glm::dvec3 extent = centres.size();
        const int axis = extent.x >= extent.y && extent.x >= extent.z ? 0 : extent.y >= extent.z ? 1 : 2;
        const std::uint32_t half = job.count / 2;
        auto begin = order_.begin() + job.first;
        std::nth_element(begin, begin + half, begin + job.count, [&](std::uint32_t a, std::uint32_t b) {
            const double ca = cellBounds_[a].min[axis] + cellBounds_[a].max[axis];
            const double cb = cellBounds_[b].min[axis] + cellBounds_[b].max[axis];
            return ca != cb ? ca < cb : a < b;
        });
        const auto left = std::uint32_t(nodes_.size());
        nodes_.push_back({});
        const auto right = std::uint32_t(nodes_.size());
        nodes_.push_back({});
        // Children are not necessarily right after their parent; keep both indices.
        nodes_[job.node].first = left;
        nodes_[job.node].right = right;
        nodes_[job.node].count = 0;
        stack.push_back({right, job.first + half, job.count - half});
        stack.push_back({left, job.first, half});
    }
}

const Aabb& CellLocator::bounds() const { return nodes_.front().box; }

}  // namespace geoslice
