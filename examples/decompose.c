/*
 * decompose: the objective decomposition of one sphere-sphere contact, printed.
 *
 * Two spheres in a general motion (translation, tumbling, rolling, sliding and twisting at once):
 * rsl_decompose splits body 1's motion relative to body 2 into the normal rate, the sliding
 * velocity, the rolling velocity and the twisting rate, plus the rigid-body parts of the pair.
 */
#include <stdio.h>

#include "rollslide.h"

static void print_vec(const char *name, rsl_vec3 v) {
    printf("  %-26s (%+.6f, %+.6f, %+.6f)\n", name, v.x, v.y, v.z);
}

int main(void) {
    /* Body 1 at the origin, body 2 along x, overlapping by 0.02 (radii 0.5 and 0.7). */
    rsl_sphere b1 = {{0.0, 0.0, 0.0}, {0.3, -0.1, 0.05}, {0.0, 0.4, 2.0}, 0.5};
    rsl_sphere b2 = {{1.18, 0.0, 0.0}, {-0.2, 0.3, 0.0}, {1.5, 0.0, -0.7}, 0.7};

    /* Options: midplane branches and the exact rolling radius (the defaults), every part. */
    rsl_decompose_options options = rsl_decompose_options_default();
    options.parts = RSL_PART_ALL;

    rsl_decomposition d;
    int32_t status = rsl_decompose(&b1, &b2, &options, &d);
    if (status != RSL_OK) {
        fprintf(stderr, "rsl_decompose: %s (%s)\n", rsl_status_str(status),
                rsl_last_error_message());
        return 1;
    }

    printf("rollslide %s: decomposition of one contact (body 1 relative to body 2)\n",
           rsl_version());
    printf("geometry\n");
    print_vec("normal n (1 -> 2)", d.normal);
    printf("  %-26s %.6f\n", "centre distance d", d.distance);
    printf("  %-26s %.6f\n", "overlap delta", d.overlap);
    printf("  %-26s %.6f, %.6f\n", "branch lengths l1, l2", d.branch1, d.branch2);
    printf("  %-26s %.6f\n", "rolling radius R_r", d.rolling_radius);
    print_vec("contact point", d.contact_point);
    printf("relative motion\n");
    printf("  %-26s %+.6f\n", "normal rate ddot", d.normal_rate);
    print_vec("sliding velocity v_s", d.sliding_velocity);
    print_vec("rolling velocity v_r", d.rolling_velocity);
    printf("  %-26s %+.6f\n", "twisting rate w_tw", d.twisting_rate);
    printf("rigid-body motion of the pair\n");
    print_vec("contact velocity v_c", d.contact_velocity);
    print_vec("tumbling w_rbr", d.tumbling);
    printf("  %-26s %+.6f\n", "frame spin w_rbs", d.frame_spin);
    print_vec("objective velocity s1", d.objective_velocity1);
    print_vec("objective velocity s2", d.objective_velocity2);

    /* The inverse map recovers the four velocities from the decomposition. */
    rsl_pair_velocities back;
    status = rsl_compose(&d, &options, &back);
    if (status != RSL_OK) {
        fprintf(stderr, "rsl_compose: %s (%s)\n", rsl_status_str(status),
                rsl_last_error_message());
        return 1;
    }
    printf("round trip through rsl_compose\n");
    print_vec("v1", back.velocity1);
    print_vec("w1", back.angular_velocity1);
    return 0;
}
