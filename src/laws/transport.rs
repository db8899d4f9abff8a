//! History transport (models.md section 1): carries a tangential history vector (a spring) from
//! the previous contact frame to the current one. Written once for every [`Real`] type.

use crate::laws::model::Transport;
use crate::scalar::{cross, dot, lit, norm_squared, select3, tangential, Real, Vec3};

/// What a transport needs to know about the step.
pub struct Frame<T: Real> {
    /// Normal of the previous step (unit; equal to `new_normal` on a contact's first step).
    pub old_normal: Vec3<T>,
    /// Current normal (unit).
    pub new_normal: Vec3<T>,
    /// Spin angle of the pair frame about `new_normal` this step: `dt w_rbs` (exact scheme).
    pub spin_angle: T,
    /// `dt (w1 + w2) . n_old / 2` (first-order scheme).
    pub half_spin_old: T,
}

/// When the project-rescale scheme acts (the other schemes ignore it).
#[derive(Clone, Copy, Debug)]
pub enum RescaleWhen<T> {
    /// Whenever the vector has a normal part (`|u . n| > 0`).
    NormalPart,
    /// LAMMPS' test `|u . n| k > 1e-10 limit` (`k` the spring's stiffness, `limit` its load
    /// limit, e.g. `mu f_n`): a spring with `k = 0` is never rescaled.
    Lammps {
        /// Stiffness `k` of the spring.
        stiffness: T,
        /// Load limit of the spring.
        limit: T,
    },
}

/// Rotates a tangential vector `u` about the unit normal `n` by `angle` without trigonometry:
/// the rational (Cayley) rotation with `t = tan(angle/2)` from its series `h + h^3/3`,
/// `h = angle/2`. The rotation is orthogonal, so lengths are kept exactly; the angle turned is
/// off by O(angle^5) (1e-17 rad at 1e-3 rad per step), below the swing-twist splitting error.
#[inline(always)]
fn spin_about<T: Real>(u: &Vec3<T>, n: &Vec3<T>, angle: T) -> Vec3<T> {
    let h = angle * lit(0.5);
    let t = h + h * h * h * lit(1.0 / 3.0);
    let t2 = t * t;
    let inv = T::one() / (T::one() + t2);
    let cos = (T::one() - t2) * inv;
    let sin = (t + t) * inv;
    u * cos + cross(n, u) * sin
}

/// Transports `u` with `scheme`; `rescale` says when project-rescale acts.
#[inline(always)]
pub fn transport<T: Real>(
    scheme: Transport,
    u: &Vec3<T>,
    frame: &Frame<T>,
    rescale: RescaleWhen<T>,
) -> Vec3<T> {
    let a = &frame.old_normal;
    let b = &frame.new_normal;
    match scheme {
        Transport::Exact => {
            // Minimal rotation a -> b: R u = u + c x u + c x (c x u)/(1 + a.b), c = a x b.
            let c = cross(a, b);
            let cos = dot(a, b);
            let one_plus = T::one() + cos;
            // A normal that flipped in one step (1 + a.b ~ 0) has no minimal rotation; fall
            // back to projection, which is what any scheme can do there.
            let ok = one_plus.simd_gt(lit(1e-12));
            let safe = crate::scalar::select(ok, one_plus, T::one());
            let cu = cross(&c, u);
            let rotated = u + cu + cross(&c, &cu) / safe;
            let swung = select3(ok, &rotated, &tangential(u, b));
            let spun = spin_about(&swung, b, frame.spin_angle);
            // Remove the rounding drift out of the tangent plane (changes |u| by O(eps^2)).
            tangential(&spun, b)
        }
        Transport::ProjectRescale => {
            let normal_part = dot(u, b);
            let projected = u - b * normal_part;
            let old_len2 = norm_squared(u);
            let new_len2 = norm_squared(&projected);
            let has_normal_part = match rescale {
                RescaleWhen::NormalPart => normal_part.simd_abs().simd_gt(T::zero()),
                RescaleWhen::Lammps { stiffness, limit } => {
                    (normal_part.simd_abs() * stiffness).simd_gt(lit::<T>(1e-10) * limit)
                }
            };
            let act = has_normal_part & new_len2.simd_gt(T::zero());
            let scale = (old_len2 / crate::scalar::select(act, new_len2, T::one())).simd_sqrt();
            select3(act, &(projected * scale), u)
        }
        Transport::FirstOrder => {
            let axis = cross(a, b);
            let v = u - cross(u, &axis);
            let twist = a * frame.half_spin_old;
            v - cross(&v, &twist)
        }
        Transport::Project => tangential(u, b),
        Transport::None => *u,
    }
}
