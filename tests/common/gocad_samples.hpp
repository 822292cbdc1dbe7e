#pragma once
// GOCAD binary sample files as the tests write them: IEEE float32, big-endian (the
// PROP_ESIZE 4 / POINTS_FILE layout that model/io/gocad/gocad_samples.cpp reads).
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace geoslice::test {

inline std::string bigEndianFloats(const std::vector<float>& v) {
    std::string out;
    out.reserve(v.size() * 4);
    for (float f : v) {
        unsigned char b[4];
        std::memcpy(b, &f, 4);
        for (int k = 3; k >= 0; --k) out.push_back(static_cast<char>(b[k]));
    }
    return out;
}

// A GOCAD group as GOCAD writes it, in `dir`: mine.gp holds a closed TSurf orebody "ore" and
// an SGrid "sg" (POINTS_FILE of big-endian float32 x y z, cell properties grade and density in
// PROP_FILEs, PROP_ALIGNMENT CELLS), attached by mine.blocks.json (clip "ore", grade in
// g/t Au). The grid: 3 x 3 x 3 cells of 10 x 10 x 5 m, sheared x = 10 i + 2 k (its k-layers
// stay horizontal slabs); grade = k + 0.5, density 2.5. The orebody [6, 24] x [2, 27] x
// [1, 13] lies inside the grid, so layer k holds 18 x 25 x (its z overlap) m³: 1800, 2250,
// 1350. The cell under a point is the sheared lattice's: (floor((x - 2z/5) / 10), floor(y /
// 10), floor(z / 5)). Returns the path of mine.gp.
inline std::filesystem::path writeShearedSGridGroup(const std::filesystem::path& dir) {
    auto write = [&](const std::string& name, const std::string& bytes) {
        std::ofstream(dir / name, std::ios::binary) << bytes;
    };
    std::vector<float> xyz, grade, density;
    for (int k = 0; k < 4; ++k)
        for (int j = 0; j < 4; ++j)
            for (int i = 0; i < 4; ++i) xyz.insert(xyz.end(), {float(10 * i + 2 * k), float(10 * j), float(5 * k)});
    for (int k = 0; k < 3; ++k)
        for (int n = 0; n < 9; ++n) {
            grade.push_back(float(k) + 0.5f);
            density.push_back(2.5f);
        }
    write("sg_points@@", bigEndianFloats(xyz));
    write("sg_grade@@", bigEndianFloats(grade));
    write("sg_density@@", bigEndianFloats(density));
    std::string tsurf = "GOCAD TSurf 1\nHEADER {\nname:ore\n}\nTFACE\n";
    const int lo[3] = {6, 2, 1}, hi[3] = {24, 27, 13};
    for (int c = 0; c < 8; ++c)
        tsurf += "VRTX " + std::to_string(c + 1) + " " + std::to_string(c & 1 ? hi[0] : lo[0]) + " " +
                 std::to_string(c & 2 ? hi[1] : lo[1]) + " " + std::to_string(c & 4 ? hi[2] : lo[2]) + "\n";
    // Outward triangles of the box (corner c + 1; bit 0 x, bit 1 y, bit 2 z).
    for (const char* t :
         {"1 3 2", "2 3 4", "5 6 7", "6 8 7", "1 2 5", "2 6 5", "3 7 4", "4 7 8", "1 5 3", "3 5 7", "2 4 6", "4 8 6"})
        tsurf += std::string("TRGL ") + t + "\n";
    tsurf += "END\n";
    const std::string sgrid =
        "GOCAD SGrid 1\nHEADER {\nname:sg\n}\nAXIS_N 4 4 4\nPROP_ALIGNMENT CELLS\nPOINTS_FILE sg_points@@\n"
        "PROPERTY 1 grade\nPROP_ESIZE 1 4\nPROP_FILE 1 sg_grade@@\n"
        "PROPERTY 2 density\nPROP_ESIZE 2 4\nPROP_FILE 2 sg_density@@\nEND\n";
    write("mine.gp",
          "GOCAD HeterogeneousGroup 1\nHEADER {\nname:mine\n}\nBEGIN_MEMBERS\n" + tsurf + sgrid + "END_MEMBERS\nEND\n");
    write("mine.blocks.json", R"({"source": "grid:sg", "clip": ["ore"], "units": {"grade": "g/t Au"}})");
    return dir / "mine.gp";
}

}  // namespace geoslice::test
