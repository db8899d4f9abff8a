//! One step of a spring-dashpot-slider (models.md section 2, steps 3-5), for a vector spring
//! (sliding, rolling; YADE's twist) and a scalar one (twisting), with its energy terms.
//! Written once for every [`Real`] type: the clip is a lane-wise select, not a branch. A load
//! whose squared length overflows (about 1.3e154 in `f64`) is clipped from a rescaled copy
//! ([`rescale_overflowed`]) in its lane only, so it gets its limit, not zero.

use crate::scalar::{
    dot, lit, mask, norm, norm_squared, rescale_overflowed, select, select3, Real, Vec3,
};
use simba::simd::SimdBool;

/// How the limit is applied when the trial load exceeds it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ClipRule {
    /// Scale the total load (spring + dashpot) to the limit and reset the spring to the part of
    /// it the dashpot does not carry: `-gamma v`, or, where `gamma |v|` alone exceeds the limit,
    /// `-limit v / |v|` (the dashpot carries at most the limit, so the spring is never reset to
    /// push against it). The objective preset's rule; YADE has no dashpot.
    Total,
    /// As `Total`, except LAMMPS' corner case: a slipping spring of zero length gives a zero
    /// load. For scalar springs also LAMMPS' sign rule: the clipped moment takes the sign of
    /// the rate (and is zero when the rate is zero).
    Lammps,
    /// The limit applies to the spring alone, scaled radially; the dashpot acts only below the
    /// limit (LIGGGHTS), so the load can exceed the limit by the dashpot.
    SpringOnly,
}

/// What the stored spring holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Storage {
    /// A displacement `xi` (length or angle): spring load `-k xi` with the current `k`
    /// (LAMMPS, LIGGGHTS sliding, the objective default).
    Displacement,
    /// The elastic load itself, built incrementally: `E += -k v dt` with the current `k`
    /// (YADE; LIGGGHTS' rolling torque). Identical to `Displacement` while `k` is constant.
    Load,
}

/// Coefficients of one spring for this step.
#[derive(Clone, Copy, Debug)]
pub struct SpringCoefficients<T: Real> {
    /// Stiffness `k` (>= 0).
    pub stiffness: T,
    /// Dashpot `gamma` (>= 0).
    pub damping: T,
    /// Load limit (>= 0, may be +inf), e.g. `mu f_n`.
    pub limit: T,
}

/// Energy terms of one spring for one step (load times displacement units).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SpringEnergy<T> {
    /// Elastic energy stored after the step, `|E|^2 / (2 k)` with `E` the spring load.
    pub elastic: T,
    /// Dissipated by the dashpot this step, `gamma |v|^2 dt` when it acted.
    pub dashpot: T,
    /// Dissipated by the slider this step: zero while the spring sticks; while it slips, the
    /// work the step's load `L` took out of the relative motion, `-L . v dt`, less the
    /// dashpot's term and the change of stored energy, so that dashpot + slider + the change
    /// of elastic energy is that work. (Not the energy the clip released, `(|E_trial|^2 -
    /// |E_new|^2) / (2 k)`: at steady slip that overstates the friction work by
    /// `k |v dt|^2 / 2` per step, and where the limit is zero it reports dissipation the load
    /// never did.) In a step without increment (a setup pass), the energy the clip released.
    pub slider: T,
}

impl<T: Real> SpringEnergy<T> {
    /// All terms zero. Always inlined: with `T` a SIMD lane type, a call left out of line
    /// would be compiled without the kernel's target features (LLVM once left it out of line
    /// in the double AVX2 batch kernel).
    #[inline(always)]
    pub fn zero() -> Self {
        SpringEnergy {
            elastic: T::zero(),
            dashpot: T::zero(),
            slider: T::zero(),
        }
    }
}

/// Result of a vector spring step.
#[derive(Clone, Copy, Debug)]
pub struct VectorSpringStep<T: Real> {
    /// The load (force or moment) on body 1.
    pub load: Vec3<T>,
    /// The spring after the step.
    pub spring: Vec3<T>,
    /// Lanes where the limit was reached.
    pub slipped: T::SimdBool,
    /// Energy terms (zero unless asked for).
    pub energy: SpringEnergy<T>,
}

/// Result of a scalar spring step.
#[derive(Clone, Copy, Debug)]
pub struct ScalarSpringStep<T: Real> {
    /// The moment on body 1 about `n`.
    pub load: T,
    /// The spring after the step.
    pub spring: T,
    /// Lanes where the limit was reached.
    pub slipped: T::SimdBool,
    /// Energy terms (zero unless asked for).
    pub energy: SpringEnergy<T>,
}

/// `|E|^2 / (2 k)`, zero where `k = 0`.
#[inline(always)]
fn energy_of<T: Real>(load2: T, k: T) -> T {
    let positive = k.simd_gt(T::zero());
    select(
        positive,
        load2 * lit(0.5) / select(positive, k, T::one()),
        T::zero(),
    )
}

/// Whether `|v| <= limit` is certain from `v2 = |v|^2` alone, so that the clip test
/// `sqrt(v2) > limit` is false without waiting for the square root. Decided only in the
/// one-lane double step (the per-contact call, where that square root is on the critical path
/// of every contact that does not slip); always false for SIMD lanes, which compute every lane
/// anyway (measured no faster there), and for `f32`.
///
/// The test is `limit >= 2^-511` and `v2 < limit^2 (1 - 2^-20)`. With `limit^2` a normal or
/// infinite double, its computed value times `1 - 2^-20` is below the exact `limit^2`, so
/// `v2 < limit^2` exactly, hence the correctly rounded `sqrt(v2)` is at most `limit`: the clip
/// test gives the same answer, and the results the same bits. NaN and infinite `v2` fail the
/// test (the exact comparison then decides).
#[inline(always)]
fn surely_within<T: Real>(v2: T, limit: T) -> bool {
    if T::LANES != 1 || std::mem::size_of::<T>() != 8 {
        return false;
    }
    let limit2 = limit * limit;
    (limit.simd_ge(lit(SURELY_WITHIN_MIN_LIMIT))
        & v2.simd_lt(limit2 * lit(1.0 - SURELY_WITHIN_MARGIN)))
    .all()
}

/// `2^-511`: from this limit up, `limit^2` is a normal double (>= 2^-1022).
const SURELY_WITHIN_MIN_LIMIT: f64 = 1.4916681462400413e-154;

/// `2^-20`: the relative margin of [`surely_within`] (far above the `2^-52` the rounding of
/// `limit^2` and of the product can take).
const SURELY_WITHIN_MARGIN: f64 = 1.0 / (1u64 << 20) as f64;

/// The length of a trial load whose squared length is `v2`, and the lanes where it exceeds
/// `limit`, or `None` when no lane does: then the clip changes nothing (its selects would all
/// pick the trial values, so skipping them changes no bit and spares its divisions). The
/// one-lane double step decides most of those cases without the square root
/// ([`surely_within`]).
#[inline(always)]
fn slipping<T: Real>(v2: T, limit: T) -> Option<(T, T::SimdBool)> {
    if surely_within(v2, limit) {
        return None;
    }
    let magnitude = v2.simd_sqrt();
    let slipped = magnitude.simd_gt(limit);
    if slipped.none() {
        None
    } else {
        Some((magnitude, slipped))
    }
}

/// Steps a vector spring: the trial spring adds `v dt` (when `increment`), the trial load is
/// the spring load minus `gamma v`, then the clip of `rule`.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
pub fn vector_spring<T: Real>(
    spring: &Vec3<T>,
    rate: &Vec3<T>,
    dt: T,
    c: &SpringCoefficients<T>,
    rule: ClipRule,
    storage: Storage,
    increment: bool,
    energy: bool,
) -> VectorSpringStep<T> {
    let zero = T::zero();
    let k = c.stiffness;
    let trial = match (increment, storage) {
        (false, _) => *spring,
        (true, Storage::Displacement) => spring + rate * dt,
        (true, Storage::Load) => spring - rate * (k * dt),
    };
    let elastic_trial = match storage {
        Storage::Displacement => trial * (-k),
        Storage::Load => trial,
    };
    let damping_load = rate * c.damping;
    let k_positive = k.simd_gt(zero);
    let safe_k = select(k_positive, k, T::one());
    // Slipping lanes whose dashpot load alone exceeds the limit ([`ClipRule::Total`] only).
    let mut capped = mask::<T>(false);
    let (load, new_spring, new_elastic, slipped, damped) = match rule {
        ClipRule::Total | ClipRule::Lammps => {
            let load = elastic_trial - damping_load;
            match slipping(norm_squared(&load), c.limit) {
                None => (
                    load,
                    trial,
                    elastic_trial,
                    mask::<T>(false),
                    mask::<T>(true),
                ),
                Some((magnitude, slipped)) => {
                    // Where |load|^2 overflowed, the load is clipped from its rescaled copy (and
                    // its true length decides whether it slips); other lanes keep their bits.
                    let (load_in_range, length, slipped) =
                        match rescale_overflowed(&load, magnitude) {
                            None => (load, magnitude, slipped),
                            Some(r) => (load / r.divisor, r.scaled_norm, r.norm.simd_gt(c.limit)),
                        };
                    let scale = c.limit / select(slipped, length, T::one());
                    let clipped = load_in_range * scale;
                    let dashpot_share = if rule == ClipRule::Total {
                        // The dashpot carries at most the limit: where `gamma |v|` alone
                        // exceeds it, its share of the clipped load is `limit v / |v|`, so the
                        // spring is never reset to push against the dashpot (with LAMMPS' rule
                        // it is, storing `|gamma v - limit|^2 / (2 k)`, without bound as
                        // `k -> 0`).
                        let d2 = norm_squared(&damping_load);
                        capped = slipped & d2.simd_gt(c.limit * c.limit);
                        if capped.any() {
                            // From a rescaled copy where |gamma v|^2 overflowed (the rule of
                            // `rescale_overflowed`, written out per component: one more nalgebra
                            // product or quotient here left nalgebra's out of line in the AVX2
                            // double kernel).
                            let d = &damping_load;
                            let length = d2.simd_sqrt();
                            let over = length.simd_eq(lit(f64::INFINITY));
                            let (divisor, length) = if over.any() {
                                let largest = d.x.simd_abs().simd_max(d.y.simd_abs());
                                let largest = largest.simd_max(d.z.simd_abs());
                                let divisor = select(over, largest, T::one());
                                let (x, y, z) = (d.x / divisor, d.y / divisor, d.z / divisor);
                                let scaled = (x * x + y * y + z * z).simd_sqrt();
                                (divisor, select(over, scaled, length))
                            } else {
                                (T::one(), length)
                            };
                            let f = c.limit / (select(capped, length, T::one()) * divisor);
                            let share = Vec3::new(d.x * f, d.y * f, d.z * f);
                            select3(capped, &share, &damping_load)
                        } else {
                            damping_load
                        }
                    } else {
                        damping_load
                    };
                    let elastic_reset = clipped + dashpot_share;
                    let spring_reset = match storage {
                        // `(-1/k) E`, one division for the three components, as LAMMPS
                        // writes it (`-1.0/k_tangential*(...)`), hence its bits.
                        Storage::Displacement => select3(
                            k_positive,
                            &(elastic_reset * (-(T::one() / safe_k))),
                            &trial,
                        ),
                        Storage::Load => elastic_reset,
                    };
                    let mut new_spring = select3(slipped, &spring_reset, &trial);
                    let mut new_elastic = select3(slipped, &elastic_reset, &elastic_trial);
                    let mut load = select3(slipped, &clipped, &load);
                    let mut damped = mask::<T>(true);
                    if rule == ClipRule::Lammps {
                        // LAMMPS: a slipping spring of zero length gives no load at all and stays
                        // empty. Not without a spring (k = 0, LAMMPS' linear_nohistory): there the
                        // load is the dashpot's, clipped.
                        let empty = slipped & k_positive & norm_squared(&trial).simd_le(zero);
                        load = select3(empty, &Vec3::zeros(), &load);
                        new_spring = select3(empty, &trial, &new_spring);
                        new_elastic = select3(empty, &elastic_trial, &new_elastic);
                        damped = !empty;
                    }
                    (load, new_spring, new_elastic, slipped, damped)
                }
            }
        }
        ClipRule::SpringOnly => {
            match slipping(norm_squared(&elastic_trial), c.limit) {
                None => {
                    let load = elastic_trial - damping_load;
                    (
                        load,
                        trial,
                        elastic_trial,
                        mask::<T>(false),
                        mask::<T>(true),
                    )
                }
                Some((magnitude, slipped)) => {
                    // As above: the spring and its load are scaled from copies divided by the
                    // same factor where |E|^2 overflowed.
                    let (trial_in_range, elastic_in_range, length, slipped) =
                        match rescale_overflowed(&elastic_trial, magnitude) {
                            None => (trial, elastic_trial, magnitude, slipped),
                            Some(r) => (
                                trial / r.divisor,
                                elastic_trial / r.divisor,
                                r.scaled_norm,
                                r.norm.simd_gt(c.limit),
                            ),
                        };
                    let scale = c.limit / select(slipped, length, T::one());
                    let new_spring = select3(slipped, &(trial_in_range * scale), &trial);
                    let new_elastic = select3(slipped, &(elastic_in_range * scale), &elastic_trial);
                    let load = select3(slipped, &new_elastic, &(new_elastic - damping_load));
                    (load, new_spring, new_elastic, slipped, !slipped)
                }
            }
        }
    };
    let energy = if energy {
        let elastic = energy_of(norm_squared(&new_elastic), k);
        let mut dashpot = select(damped, c.damping * norm_squared(rate) * dt, zero);
        if capped.any() {
            // The capped dashpot's work: its share `limit v / |v|` times `v dt`.
            dashpot = select(capped, c.limit * norm(rate) * dt, dashpot);
        }
        // The energy the clip released: zero to the bit where the spring sticks.
        let released = energy_of(norm_squared(&elastic_trial), k) - elastic;
        let slider = if increment && slipped.any() {
            // |E|^2 of the spring before the step, E = -k xi or the stored load (no nalgebra
            // product here: one more use kept it out of line in the AVX2 kernel).
            let before2 = match storage {
                Storage::Displacement => norm_squared(spring) * (k * k),
                Storage::Load => norm_squared(spring),
            };
            let work = -dot(&load, rate) * dt;
            let stored = elastic - energy_of(before2, k);
            select(slipped, work - dashpot - stored, released)
        } else {
            released
        };
        SpringEnergy {
            elastic,
            dashpot,
            slider,
        }
    } else {
        SpringEnergy::zero()
    };
    VectorSpringStep {
        load,
        spring: new_spring,
        slipped,
        energy,
    }
}

/// `1`, `-1` or `0` as `x` is positive, negative or zero (or NaN), lane-wise.
#[inline(always)]
fn sign_of<T: Real>(x: T) -> T {
    let (zero, one) = (T::zero(), T::one());
    select(x.simd_gt(zero), one, select(x.simd_lt(zero), -one, zero))
}

/// Steps a scalar (twisting) spring stored as a displacement (angle); see [`vector_spring`].
/// Under [`ClipRule::Total`] the clipped moment keeps the sign of the trial moment; under
/// [`ClipRule::Lammps`] it takes the sign of the rate (zero when the rate is zero).
#[inline(always)]
pub fn scalar_spring<T: Real>(
    spring: T,
    rate: T,
    dt: T,
    c: &SpringCoefficients<T>,
    rule: ClipRule,
    increment: bool,
    energy: bool,
) -> ScalarSpringStep<T> {
    let zero = T::zero();
    let one = T::one();
    let trial = if increment {
        spring + rate * dt
    } else {
        spring
    };
    let damping_load = rate * c.damping;
    let k_positive = c.stiffness.simd_gt(zero);
    let safe_k = select(k_positive, c.stiffness, one);
    // Slipping lanes whose dashpot moment alone exceeds the limit ([`ClipRule::Total`] only).
    let mut capped = mask::<T>(false);
    let (load, new_spring, slipped, damped) = match rule {
        ClipRule::Total | ClipRule::Lammps => {
            let load = -c.stiffness * trial - damping_load;
            let slipped = load.simd_abs().simd_gt(c.limit);
            if slipped.none() {
                (load, trial, slipped, mask::<T>(true))
            } else {
                let direction = if rule == ClipRule::Lammps {
                    -sign_of(rate)
                } else {
                    sign_of(load)
                };
                let clipped = c.limit * direction;
                // As in `vector_spring`: under the objective rule the dashpot carries at most
                // the limit.
                let dashpot_share = if rule == ClipRule::Total {
                    capped = slipped & damping_load.simd_abs().simd_gt(c.limit);
                    select(capped, sign_of(damping_load) * c.limit, damping_load)
                } else {
                    damping_load
                };
                // `(1/k) (-M)`, as LAMMPS writes it (`1.0/k_twist*(...)`), hence its bits.
                let reset = select(
                    k_positive,
                    -(clipped + dashpot_share) * (one / safe_k),
                    trial,
                );
                (
                    select(slipped, clipped, load),
                    select(slipped, reset, trial),
                    slipped,
                    mask::<T>(true),
                )
            }
        }
        ClipRule::SpringOnly => {
            let spring_load = -c.stiffness * trial;
            let slipped = spring_load.simd_abs().simd_gt(c.limit);
            if slipped.none() {
                (spring_load - damping_load, trial, slipped, !slipped)
            } else {
                let scale = c.limit / select(slipped, spring_load.simd_abs(), one);
                let new_spring = select(slipped, trial * scale, trial);
                let spring_load = -c.stiffness * new_spring;
                (
                    select(slipped, spring_load, spring_load - damping_load),
                    new_spring,
                    slipped,
                    !slipped,
                )
            }
        }
    };
    let energy = if energy {
        let half_k = c.stiffness * lit(0.5);
        let elastic = half_k * new_spring * new_spring;
        let mut dashpot = select(damped, c.damping * rate * rate * dt, zero);
        if capped.any() {
            dashpot = select(capped, c.limit * rate.simd_abs() * dt, dashpot);
        }
        // As in `vector_spring`.
        let released = half_k * trial * trial - elastic;
        let slider = if increment && slipped.any() {
            let work = -load * rate * dt;
            let stored = elastic - half_k * spring * spring;
            select(slipped, work - dashpot - stored, released)
        } else {
            released
        };
        SpringEnergy {
            elastic,
            dashpot,
            slider,
        }
    } else {
        SpringEnergy::zero()
    };
    ScalarSpringStep {
        load,
        spring: new_spring,
        slipped,
        energy,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;
    use simba::simd::SimdValue;

    /// LAMMPS' empty-spring rule (a slipping spring of zero length gives no load) is a rule of
    /// a spring: with `k = 0` (LAMMPS' `linear_nohistory`) a slipping dashpot still gives its
    /// load clipped at the limit, `-limit v / |v|`, as stock's no-history branch does, also in a
    /// setup pass of a fresh contact; with `k > 0` the rule holds.
    #[test]
    fn the_lammps_empty_spring_rule_needs_a_spring() {
        let rate = Vec3::new(3.0, -4.0, 0.0);
        for (k, want) in [(0.0, Vec3::new(-1.2, 1.6, 0.0)), (50.0, Vec3::zeros())] {
            let c = SpringCoefficients {
                stiffness: k,
                damping: 1.0,
                limit: 2.0,
            };
            let r = vector_spring::<f64>(
                &Vec3::zeros(),
                &rate,
                1e-3,
                &c,
                ClipRule::Lammps,
                Storage::Displacement,
                false,
                false,
            );
            assert!(r.slipped, "k = {k}");
            assert!((r.load - want).norm() < 1e-15, "k = {k}: {:?}", r.load);
        }
    }

    /// The clip's own test, as `vector_spring` computes it after the square root.
    fn clip_test_slips(v2: f64, limit: f64) -> bool {
        v2.sqrt() > limit
    }

    /// `surely_within` may say "within" only where the clip test says "does not slip".
    fn check(v2: f64, limit: f64) {
        if surely_within(v2, limit) {
            assert!(
                !clip_test_slips(v2, limit),
                "surely_within({v2:e}, {limit:e}) but sqrt(v2) = {:e} > limit",
                v2.sqrt()
            );
        }
    }

    #[test]
    fn surely_within_never_hides_a_slip_near_the_limit() {
        let mut limits = vec![
            SURELY_WITHIN_MIN_LIMIT,
            SURELY_WITHIN_MIN_LIMIT.next_down(),
            SURELY_WITHIN_MIN_LIMIT.next_up(),
            f64::MIN_POSITIVE,
            1e-300,
            1e-160,
            f64::MAX.sqrt(),
            f64::MAX.sqrt().next_up(),
            f64::MAX,
            f64::INFINITY,
            0.0,
            -1.0,
            f64::NAN,
        ];
        let mut x = 1.0e-200;
        while x < 1.0e200 {
            limits.push(x);
            limits.push(x * 1.000_000_3);
            x *= 7.3;
        }
        for &limit in &limits {
            let l2 = limit * limit;
            let mut candidates = vec![0.0, f64::INFINITY, f64::NAN, f64::MAX, l2];
            let (mut below, mut above) = (l2, l2);
            for _ in 0..64 {
                below = below.next_down();
                above = above.next_up();
                candidates.extend([below, above]);
            }
            // Just inside and outside the margin.
            let edge = l2 * (1.0 - SURELY_WITHIN_MARGIN);
            let (mut e0, mut e1) = (edge, edge);
            for _ in 0..64 {
                e0 = e0.next_down();
                e1 = e1.next_up();
                candidates.extend([e0, e1]);
            }
            for v2 in candidates {
                check(v2, limit);
            }
        }
    }

    #[test]
    fn surely_within_takes_the_plain_no_slip_case() {
        // The case it is for: a load well below a limit of ordinary size.
        assert!(surely_within(0.25f64, 1.0));
        assert!(surely_within(1e-30f64, 1e-12));
        // Never for SIMD lanes or single precision (those compute the square root).
        assert!(!surely_within(0.25f32, 1.0));
        type Lanes4 = simba::simd::WideF64x4;
        assert!(!surely_within(Lanes4::splat(0.25), Lanes4::splat(1.0)));
        // Not at the limit, not for a tiny or negative limit, NaN or an infinite load.
        assert!(!surely_within(1.0f64, 1.0));
        assert!(!surely_within(0.0f64, SURELY_WITHIN_MIN_LIMIT.next_down()));
        assert!(!surely_within(0.0f64, -1.0));
        assert!(!surely_within(f64::NAN, 1.0));
        assert!(!surely_within(f64::INFINITY, f64::INFINITY));
    }

    #[test]
    fn surely_within_constants_are_the_powers_of_two_they_name() {
        assert_eq!(SURELY_WITHIN_MIN_LIMIT, 2f64.powi(-511));
        assert!((SURELY_WITHIN_MIN_LIMIT * SURELY_WITHIN_MIN_LIMIT).is_normal());
        assert_eq!(SURELY_WITHIN_MARGIN, 2f64.powi(-20));
    }

    proptest! {
        #[test]
        fn surely_within_implies_no_slip_for_any_doubles(
            v2 in any::<f64>(),
            limit in any::<f64>(),
        ) {
            check(v2, limit);
        }

        #[test]
        fn surely_within_implies_no_slip_near_the_limit(
            limit in 1e-150f64..1e150,
            rel in -1e-5f64..1e-5,
        ) {
            check(limit * limit * (1.0 + rel), limit);
        }
    }
}
