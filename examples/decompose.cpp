// decompose.cpp: the C header used from C++11 -- a ball rolling and sliding on a moving wall,
// decomposed with rsl_decompose_wall, plus a check that the header and the library versions agree.
#include "rollslide.h"

#include <cstdint>
#include <cstdio>
#include <string>

namespace {

// A thin C++ wrapper: a failed call becomes an exception carrying the library's message.
struct rollslide_error {
    std::string message;
};

void check(std::int32_t status, const char *what) {
    if (status != RSL_OK)
        throw rollslide_error{std::string(what) + ": " + rsl_status_str(status) + " (" +
                              rsl_last_error_message() + ")"};
}

rsl_vec3 vec(double x, double y, double z) { return rsl_vec3{x, y, z}; }

void print(const char *name, const rsl_vec3 &v) {
    std::printf("  %-22s (%+.6f, %+.6f, %+.6f)\n", name, v.x, v.y, v.z);
}

}  // namespace

int main() {
    const std::string header_version = std::to_string(RSL_VERSION_MAJOR) + "." +
                                       std::to_string(RSL_VERSION_MINOR) + "." +
                                       std::to_string(RSL_VERSION_PATCH);
    if (header_version != rsl_version()) {
        std::fprintf(stderr, "header %s but library %s\n", header_version.c_str(), rsl_version());
        return 1;
    }
    try {
        // A ball of radius 0.5 resting 0.001 into the floor z = 0, moving along x at 1.0 and
        // spinning a little slower than rolling would need: it rolls and slides at once.
        rsl_sphere ball{vec(0.0, 0.0, 0.499), vec(1.0, 0.0, 0.0), vec(0.0, 1.6, 0.3), 0.5};
        // The floor (outward normal +z) translates along y at 0.2.
        rsl_wall floor{vec(0, 0, 0), vec(0, 0, 1), vec(0.0, 0.2, 0.0), vec(0, 0, 0)};

        rsl_decomposition d;
        check(rsl_decompose_wall(&ball, &floor, nullptr, &d), "rsl_decompose_wall");
        std::printf("rollslide %s from C++: ball on a moving floor\n", rsl_version());
        print("normal n", d.normal);
        std::printf("  %-22s %.6f (wall: R_r = l1)\n", "rolling radius", d.rolling_radius);
        print("sliding velocity", d.sliding_velocity);
        print("rolling velocity", d.rolling_velocity);
        std::printf("  %-22s %+.6f\n", "twisting rate", d.twisting_rate);

        // An invalid input is reported, not a crash: a zero wall normal.
        rsl_wall bad = floor;
        bad.normal = vec(0, 0, 0);
        try {
            check(rsl_decompose_wall(&ball, &bad, nullptr, &d), "rsl_decompose_wall");
            return 1;  // must not get here
        } catch (const rollslide_error &e) {
            std::printf("error reported as expected: %s\n", e.message.c_str());
        }
    } catch (const rollslide_error &e) {
        std::fprintf(stderr, "%s\n", e.message.c_str());
        return 1;
    }
    return 0;
}
