/*
 * rollslide.hpp: a header-only C++11 wrapper of rollslide.h.
 *
 * - Everything is in namespace `rollslide`; the plain C structs (rsl_sphere, rsl_wall,
 *   rsl_contact_input, rsl_contact_state, rsl_contact_loads, rsl_decomposition...) are used
 *   as they are.
 * - `rollslide::model` owns an rsl_model: created by its constructor, released by its
 *   destructor, movable, not copyable (share it by reference: a model is read-only during
 *   steps, so many threads may step with one model at once).
 * - A failed call throws `rollslide::error`, which carries the status code (`status()`, an
 *   RSL_ERR_* value) and the library's message. Outputs and states are untouched on failure,
 *   as in C.
 * - The step calls are inline: one call of the C function and one test of its status.
 *
 * Link as for the C header (CMake: `rollslide::rollslide`; pkg-config: `rollslide`).
 */
#ifndef ROLLSLIDE_HPP
#define ROLLSLIDE_HPP

#include "rollslide.h"

#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace rollslide {

/// A failed rollslide call: the status code and the library's message.
class error : public std::runtime_error {
public:
    error(int32_t status, const std::string &message)
        : std::runtime_error(message), status_(status) {}
    /// The RSL_ERR_* status of the failed call.
    int32_t status() const noexcept { return status_; }

private:
    int32_t status_;
};

namespace detail {

/// Throws the error of `status` (not RSL_OK) returned by `call`, with the thread's last message.
[[noreturn]] inline void fail(int32_t status, const char *call) {
    // The thread's last message names the failure and the field; the status name stands in
    // when there is none.
    const char *detail = rsl_last_error_message();
    std::string message(call);
    message += ": ";
    message += (detail != nullptr && detail[0] != '\0') ? detail : rsl_status_str(status);
    throw error(status, message);
}

/// Throws unless `status` is RSL_OK.
inline void check(int32_t status, const char *call) {
    if (status != RSL_OK) {
        fail(status, call);
    }
}

} // namespace detail

/// The library's version string ("major.minor.patch").
inline const char *version() noexcept { return rsl_version(); }

/// The RSL_SIMD_* levels this CPU offers to the batch calls (a bit mask, see rollslide.h).
inline uint32_t batch_simd_support() noexcept { return rsl_batch_simd_support(); }

/// Default decomposition options (every part, midplane branches, exact rolling radius).
inline rsl_decompose_options decompose_options() noexcept {
    return rsl_decompose_options_default();
}

/// Decomposition of a sphere pair (`options`: NULL for the defaults).
inline rsl_decomposition decompose(const rsl_sphere &body1, const rsl_sphere &body2,
                                   const rsl_decompose_options *options = nullptr) {
    rsl_decomposition d;
    detail::check(rsl_decompose(&body1, &body2, options, &d), "rsl_decompose");
    return d;
}

/// Decomposition of a sphere on a flat wall (body 2).
inline rsl_decomposition decompose(const rsl_sphere &sphere, const rsl_wall &wall,
                                   const rsl_decompose_options *options = nullptr) {
    rsl_decomposition d;
    detail::check(rsl_decompose_wall(&sphere, &wall, options, &d), "rsl_decompose_wall");
    return d;
}

/// The pair velocities a decomposition stands for (the inverse map).
inline rsl_pair_velocities compose(const rsl_decomposition &d,
                                   const rsl_decompose_options *options = nullptr) {
    rsl_pair_velocities v;
    detail::check(rsl_compose(&d, options, &v), "rsl_compose");
    return v;
}

/// The sphere's velocities a wall decomposition stands for.
inline rsl_wall_velocities compose_wall(const rsl_decomposition &d,
                                        const rsl_decompose_options *options = nullptr) {
    rsl_wall_velocities v;
    detail::check(rsl_compose_wall(&d, options, &v), "rsl_compose_wall");
    return v;
}

/// Critical time step of velocity Verlet for a rotational spring-dashpot (see rollslide.h).
inline double rotational_critical_time_step(double k_theta, double inertia1, double inertia2,
                                            double damping_ratio) {
    double dt = 0.0;
    detail::check(rsl_rotational_critical_time_step(k_theta, inertia1, inertia2, damping_ratio,
                                                    &dt),
                  "rsl_rotational_critical_time_step");
    return dt;
}

/// Stable step bound with sliding and rotational springs coupled (see rollslide.h).
inline double coupled_critical_time_step(double k_t, double k_theta, double mass1, double mass2,
                                         double inertia1, double inertia2, double l1, double l2) {
    double dt = 0.0;
    detail::check(rsl_coupled_critical_time_step(k_t, k_theta, mass1, mass2, inertia1, inertia2,
                                                 l1, l2, &dt),
                  "rsl_coupled_critical_time_step");
    return dt;
}

/// A fresh (all-zero) contact state: what a new contact starts from, and what a contact is reset
/// to when its pair separates.
inline rsl_contact_state fresh_state() {
    rsl_contact_state s;
    detail::check(rsl_contact_state_init(&s), "rsl_contact_state_init");
    return s;
}

/// A contact model (laws, parameters, transport, preset), owning its rsl_model.
class model {
public:
    /// A model of `preset` (RSL_PRESET_OBJECTIVE, _LAMMPS_2021, _YADE_2023, _LIGGGHTS_3_8).
    explicit model(int32_t preset = RSL_PRESET_OBJECTIVE) : handle_(nullptr) {
        detail::check(rsl_model_new(preset, &handle_), "rsl_model_new");
    }
    ~model() { rsl_model_free(handle_); }
    model(model &&other) noexcept : handle_(other.handle_) { other.handle_ = nullptr; }
    model &operator=(model &&other) noexcept {
        if (this != &other) {
            rsl_model_free(handle_);
            handle_ = other.handle_;
            other.handle_ = nullptr;
        }
        return *this;
    }
    model(const model &) = delete;
    model &operator=(const model &) = delete;

    /// The C handle (NULL after the model was moved from), for the C functions.
    rsl_model *get() noexcept { return handle_; }
    /// The C handle, read only.
    const rsl_model *get() const noexcept { return handle_; }

    /// Branch rule (RSL_BRANCH_*) and rolling radius rule (RSL_ROLLING_RADIUS_*).
    model &set_geometry(int32_t branch_rule, int32_t rolling_radius_rule) {
        detail::check(rsl_model_set_geometry(handle_, branch_rule, rolling_radius_rule),
                      "rsl_model_set_geometry");
        return *this;
    }
    /// Sliding law (RSL_SLIDING_*), `k_t` (force/length), `gamma_t` (force time/length),
    /// `mu_s` (1; +INFINITY: no limit).
    model &set_sliding(int32_t law, double stiffness, double damping, double friction) {
        detail::check(rsl_model_set_sliding(handle_, law, stiffness, damping, friction),
                      "rsl_model_set_sliding");
        return *this;
    }
    /// Twisting law (RSL_TWISTING_*) and its stiffness, damping and friction (see rollslide.h).
    model &set_twisting(int32_t law, double stiffness, double damping, double friction) {
        detail::check(rsl_model_set_twisting(handle_, law, stiffness, damping, friction),
                      "rsl_model_set_twisting");
        return *this;
    }
    /// Rolling resistance law and its parameters.
    model &set_rolling(const rsl_rolling_params &params) {
        detail::check(rsl_model_set_rolling(handle_, &params), "rsl_model_set_rolling");
        return *this;
    }
    /// The rolling resistance law and its parameters.
    rsl_rolling_params rolling() const {
        rsl_rolling_params p;
        detail::check(rsl_model_get_rolling(handle_, &p), "rsl_model_get_rolling");
        return p;
    }
    /// History transport of the sliding and of the rolling/twisting springs (RSL_TRANSPORT_*).
    model &set_transport(int32_t sliding_scheme, int32_t rolling_scheme) {
        detail::check(rsl_model_set_transport(handle_, sliding_scheme, rolling_scheme),
                      "rsl_model_set_transport");
        return *this;
    }
    /// Energy terms in the outputs of `step` (off by default; the batch calls refuse it).
    model &set_energy_tracking(bool enabled) {
        detail::check(rsl_model_set_energy_tracking(handle_, enabled ? 1 : 0),
                      "rsl_model_set_energy_tracking");
        return *this;
    }
    /// The table of material pairs the batch calls index with
    /// `rsl_batch_contact_params::material` (`rsl_model_set_materials`): set `i` takes the
    /// coefficients of `*sets[i]`, a model of the same laws; `n = 0` removes the table.
    model &set_materials(const model *const *sets, std::size_t n) {
        std::vector<const rsl_model *> handles(n);
        for (std::size_t i = 0; i < n; i++) handles[i] = sets[i]->handle_;
        detail::check(rsl_model_set_materials(handle_, handles.data(), n),
                      "rsl_model_set_materials");
        return *this;
    }

    /// Mirrors `state` for the same contact with body 1 and body 2 exchanged
    /// (`rsl_contact_state_swap`): stepping (body2, body1) from it mirrors the original order.
    void swap_state(rsl_contact_state &state) const {
        detail::check(rsl_contact_state_swap(handle_, &state), "rsl_contact_state_swap");
    }
    /// One step of a sphere pair: advances `state`, returns the loads (force on body 1,
    /// `-f_n n + F_t`, torques on both bodies, and the parts).
    rsl_contact_loads step(const rsl_sphere &body1, const rsl_sphere &body2,
                           const rsl_contact_input &input, rsl_contact_state &state) const {
        rsl_contact_loads out;
        detail::check(rsl_contact_step(handle_, &body1, &body2, &input, &state, &out),
                      "rsl_contact_step");
        return out;
    }
    /// One step of a sphere pair, the loads added to the host's accumulators:
    /// `force1 += F`, `torque1 += T1`, `force2 -= F`, `torque2 += T2`.
    void step_accumulate(const rsl_sphere &body1, const rsl_sphere &body2,
                         const rsl_contact_input &input, rsl_contact_state &state,
                         rsl_vec3 &force1, rsl_vec3 &torque1, rsl_vec3 &force2,
                         rsl_vec3 &torque2) const {
        detail::check(rsl_contact_step_accumulate(handle_, &body1, &body2, &input, &state,
                                                  &force1, &torque1, &force2, &torque2),
                      "rsl_contact_step_accumulate");
    }
    /// One step of a sphere on a flat wall (body 2).
    rsl_contact_loads step(const rsl_sphere &sphere, const rsl_wall &wall,
                           const rsl_contact_input &input, rsl_contact_state &state) const {
        rsl_contact_loads out;
        detail::check(rsl_contact_step_wall(handle_, &sphere, &wall, &input, &state, &out),
                      "rsl_contact_step_wall");
        return out;
    }
    /// One step of a sphere on a wall, the loads added to the sphere's accumulators.
    void step_accumulate(const rsl_sphere &sphere, const rsl_wall &wall,
                         const rsl_contact_input &input, rsl_contact_state &state,
                         rsl_vec3 &force, rsl_vec3 &torque) const {
        detail::check(rsl_contact_step_wall_accumulate(handle_, &sphere, &wall, &input, &state,
                                                       &force, &torque),
                      "rsl_contact_step_wall_accumulate");
    }

    /// Steps many contacts (particle-major, see rsl_batch_step; with `params`, per-contact
    /// sliding stiffness and damping, rsl_batch_step_params). A contact with bad input is
    /// skipped and the others are processed: that is reported in the returned report
    /// (`failed`, `first_failed`, `first_status`), not thrown. A call-level error (NULL array,
    /// bad time step or options), which processes nothing, throws.
    rsl_batch_report batch_step(const rsl_sphere *particles, std::size_t n_particles,
                                const uint32_t *pairs, std::size_t n_contacts,
                                const double *normal_force, const double *normal_stiffness,
                                double dt, rsl_contact_state *states, rsl_vec3 *force,
                                rsl_vec3 *torque, const rsl_batch_options *options = nullptr,
                                const rsl_batch_contact_params *params = nullptr) const {
        rsl_batch_report report;
        int32_t status = rsl_batch_step_params(handle_, particles, n_particles, pairs,
                                               n_contacts, normal_force, normal_stiffness,
                                               params, dt, options, states, force, torque,
                                               &report);
        if (status != RSL_OK && report.failed == 0) {
            detail::fail(status, "rsl_batch_step_params");
        }
        return report;
    }
    /// Steps many contacts (contact-major, see rsl_batch_step_contacts; with `params`,
    /// rsl_batch_step_contacts_params); errors as batch_step.
    rsl_batch_report batch_step_contacts(const rsl_sphere *body1, const rsl_sphere *body2,
                                         std::size_t n, const double *normal_force,
                                         const double *normal_stiffness, double dt,
                                         rsl_contact_state *states, rsl_batch_loads *out,
                                         const rsl_batch_options *options = nullptr,
                                         const rsl_batch_contact_params *params = nullptr) const {
        rsl_batch_report report;
        int32_t status = rsl_batch_step_contacts_params(handle_, body1, body2, n, normal_force,
                                                        normal_stiffness, params, dt, options,
                                                        states, out, &report);
        if (status != RSL_OK && report.failed == 0) {
            detail::fail(status, "rsl_batch_step_contacts_params");
        }
        return report;
    }

private:
    rsl_model *handle_;
};

} // namespace rollslide

#endif // ROLLSLIDE_HPP
