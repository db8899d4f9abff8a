//! Time-step helpers (models.md section 5). A wall is body 2 with infinite mass and inertia:
//! pass `f64::INFINITY` (its inverse is 0).

use crate::error::Error;

fn check(x: f64, what: &'static str, allow_infinite: bool) -> Result<(), Error> {
    if x.is_nan() || (x.is_infinite() && !(allow_infinite && x > 0.0)) {
        return Err(Error::NonFinite(what));
    }
    let ok = x > 0.0 && (x.is_finite() || (allow_infinite && x == f64::INFINITY));
    if ok {
        Ok(())
    } else {
        Err(Error::InvalidArgument(format!("{what} = {x} must be > 0")))
    }
}

/// Refuses a bound that under- or overflowed (extreme but finite inputs): never `Ok(inf)`.
fn finite_result(dt: f64) -> Result<f64, Error> {
    if dt.is_finite() && dt > 0.0 {
        Ok(dt)
    } else {
        Err(Error::NonFinite("result overflowed (inputs too extreme)"))
    }
}

/// Critical time step of velocity Verlet for the rotational spring-dashpot of two bodies:
/// `w0 = sqrt(k_theta (1/I1 + 1/I2))`, `dt_c = (2/w0)(sqrt(1 + z^2) - z)`.
///
/// `k_theta`: rolling (or twisting) stiffness in moment/rad (> 0); `inertia1`, `inertia2`: moments
/// of inertia (> 0, `inertia2` may be +inf for a wall); `damping_ratio`: `z >= 0`.
pub fn rotational_critical_time_step(
    k_theta: f64,
    inertia1: f64,
    inertia2: f64,
    damping_ratio: f64,
) -> Result<f64, Error> {
    check(k_theta, "k_theta", false)?;
    check(inertia1, "inertia1", false)?;
    check(inertia2, "inertia2", true)?;
    if !damping_ratio.is_finite() {
        return Err(Error::NonFinite("damping_ratio"));
    }
    if damping_ratio < 0.0 {
        return Err(Error::InvalidArgument(format!(
            "damping_ratio = {damping_ratio} must be finite and >= 0"
        )));
    }
    let w0 = (k_theta * (1.0 / inertia1 + 1.0 / inertia2)).sqrt();
    let z = damping_ratio;
    // sqrt(1 + z^2) - z written as 1/(sqrt(1 + z^2) + z): no cancellation for large z (the
    // difference form loses every digit from z ~ 1e8 on and returns 0 there).
    finite_result((2.0 / w0) / ((1.0 + z * z).sqrt() + z))
}

/// Stable time step bound with the sliding spring coupled to the rotational one:
/// `dt <= 2 / sqrt(k_t (1/m1 + 1/m2 + l1^2/I1 + l2^2/I2) + k_theta (1/I1 + 1/I2))`.
///
/// `k_t` (force/length) and `k_theta` (moment/rad) >= 0, not both 0; masses and inertias > 0
/// (body 2's may be +inf for a wall); `l1`, `l2` the branch lengths (> 0; `l2` is not read,
/// so not checked, when `inertia2` is +inf: its term `l2^2/I2` is 0, and a wall's `l2` is
/// +inf).
#[allow(clippy::too_many_arguments)]
pub fn coupled_critical_time_step(
    k_t: f64,
    k_theta: f64,
    mass1: f64,
    mass2: f64,
    inertia1: f64,
    inertia2: f64,
    l1: f64,
    l2: f64,
) -> Result<f64, Error> {
    for (x, what) in [(k_t, "k_t"), (k_theta, "k_theta")] {
        if !x.is_finite() {
            return Err(Error::NonFinite(what));
        }
        if x < 0.0 {
            return Err(Error::InvalidArgument(format!("{what} = {x} must be >= 0")));
        }
    }
    if k_t == 0.0 && k_theta == 0.0 {
        return Err(Error::InvalidArgument(
            "k_t and k_theta are both 0: no bound".to_string(),
        ));
    }
    check(mass1, "mass1", false)?;
    check(mass2, "mass2", true)?;
    check(inertia1, "inertia1", false)?;
    check(inertia2, "inertia2", true)?;
    check(l1, "l1", false)?;
    let arm2 = if inertia2.is_infinite() {
        0.0
    } else {
        check(l2, "l2", false)?;
        l2 * l2 / inertia2
    };
    let s = k_t * (1.0 / mass1 + 1.0 / mass2 + l1 * l1 / inertia1 + arm2)
        + k_theta * (1.0 / inertia1 + 1.0 / inertia2);
    finite_result(2.0 / s.sqrt())
}
