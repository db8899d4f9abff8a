//! The batch slot traits for the C layouts of [`crate::layout`]: how the kernels read an
//! `rsl_sphere`, an `rsl_wall` and an `rsl_contact_state`, add to an `rsl_vec3` accumulator and
//! write an `rsl_batch_loads` (also as the nine doubles the SIMD copiers transpose into), and
//! which cache lines they prefetch for each.

use super::prefetch::{prefetch, prefetch_at};
use super::{AddSlot, LoadsSlot, PairLoads, SphereSlot, StateSlot, WallSlot, WALL_WORDS};
use crate::decompose::Sphere;
use crate::laws::step::ContactState;
use crate::layout::{rsl_batch_loads, rsl_contact_state, rsl_sphere, rsl_vec3, rsl_wall};

impl SphereSlot for rsl_sphere {
    #[inline(always)]
    fn sphere(&self) -> Sphere<f64> {
        Sphere::from(self)
    }
    #[inline(always)]
    fn touch(&self) {
        // An rsl_sphere is 80 bytes: it may straddle two cache lines.
        prefetch(&self.position.x);
        prefetch(&self.radius);
    }
    #[inline(always)]
    fn touch_in(slots: &[Self], i: usize) {
        prefetch_at(slots, i, 0);
        prefetch_at(slots, i, std::mem::offset_of!(rsl_sphere, radius));
    }
}

impl StateSlot for rsl_contact_state {
    #[inline(always)]
    fn load(&self) -> ContactState<f64> {
        ContactState::from(self)
    }
    #[inline(always)]
    fn store(&mut self, s: &ContactState<f64>, slip: u32) {
        self.sliding_spring = s.sliding_spring.into();
        self.rolling_spring = s.rolling_spring.into();
        self.twisting_angle = s.twisting_angle;
        self.model_memory = s.model_memory.into();
        self.previous_normal = s.previous_normal.into();
        self.slip_flags = slip;
    }
    #[inline(always)]
    fn touch(&self) {
        // 112 bytes: two or three cache lines.
        prefetch(&self.sliding_spring.x);
        prefetch(&self.model_memory.x);
        prefetch(&self.slip_flags);
    }
    #[inline(always)]
    fn touch_in(slots: &[Self], i: usize) {
        prefetch_at(slots, i, 0);
        prefetch_at(
            slots,
            i,
            std::mem::offset_of!(rsl_contact_state, model_memory),
        );
        prefetch_at(
            slots,
            i,
            std::mem::offset_of!(rsl_contact_state, slip_flags),
        );
    }
}

impl WallSlot for rsl_wall {
    #[inline(always)]
    fn words(&self) -> [f64; WALL_WORDS] {
        let (p, n, v, w) = (
            &self.point,
            &self.normal,
            &self.velocity,
            &self.angular_velocity,
        );
        [p.x, p.y, p.z, n.x, n.y, n.z, v.x, v.y, v.z, w.x, w.y, w.z]
    }
    #[inline(always)]
    fn doubles(&self) -> Option<&[f64; WALL_WORDS]> {
        const _: () = assert!(std::mem::size_of::<rsl_wall>() == WALL_WORDS * 8);
        const _: () = assert!(std::mem::offset_of!(rsl_wall, normal) == 24);
        const _: () = assert!(std::mem::offset_of!(rsl_wall, velocity) == 48);
        const _: () = assert!(std::mem::offset_of!(rsl_wall, angular_velocity) == 72);
        // SAFETY: `rsl_wall` is `repr(C)`: four `rsl_vec3` (each `repr(C)`, three `f64`) at
        // offsets 0, 24, 48, 72 and size 96 (asserted above), in `WALL_WORDS` order: the layout
        // of `[f64; 12]` with the same alignment. The result borrows `self`.
        Some(unsafe { &*(self as *const rsl_wall).cast::<[f64; WALL_WORDS]>() })
    }
    #[inline(always)]
    fn touch_in(slots: &[Self], i: usize) {
        // 96 bytes: two or three cache lines.
        prefetch_at(slots, i, 0);
        prefetch_at(slots, i, std::mem::offset_of!(rsl_wall, velocity));
        prefetch_at(slots, i, std::mem::offset_of!(rsl_wall, angular_velocity.z));
    }
}

impl AddSlot for rsl_vec3 {
    #[inline(always)]
    fn add(&mut self, v: [f64; 3]) {
        self.x += v[0];
        self.y += v[1];
        self.z += v[2];
    }
    #[inline(always)]
    fn get(&self) -> [f64; 3] {
        [self.x, self.y, self.z]
    }
    #[inline(always)]
    fn set(&mut self, v: [f64; 3]) {
        *self = vec(v);
    }
    #[inline(always)]
    fn touch(&self) {
        // 24 bytes: may straddle two cache lines.
        prefetch(&self.x);
        prefetch(&self.z);
    }
    #[inline(always)]
    fn touch_in(slots: &[Self], i: usize) {
        prefetch_at(slots, i, 0);
        prefetch_at(slots, i, std::mem::offset_of!(rsl_vec3, z));
    }
}

fn vec(a: [f64; 3]) -> rsl_vec3 {
    rsl_vec3 {
        x: a[0],
        y: a[1],
        z: a[2],
    }
}

impl LoadsSlot for rsl_batch_loads {
    #[inline(always)]
    fn set(&mut self, l: &PairLoads) {
        *self = rsl_batch_loads {
            force1: vec(l.force1),
            torque1: vec(l.torque1),
            torque2: vec(l.torque2),
        };
    }
    #[inline(always)]
    fn words_mut(&mut self) -> Option<&mut [f64; 9]> {
        const _: () = assert!(std::mem::size_of::<rsl_batch_loads>() == 72);
        const _: () = assert!(std::mem::offset_of!(rsl_batch_loads, torque1) == 24);
        const _: () = assert!(std::mem::offset_of!(rsl_batch_loads, torque2) == 48);
        // SAFETY: `rsl_batch_loads` is `repr(C)`: three `rsl_vec3` (each `repr(C)`, three
        // `f64`) at offsets 0, 24, 48 and size 72 (asserted above), the layout of `[f64; 9]`
        // with the same alignment. The result borrows `self` mutably.
        Some(unsafe { &mut *(self as *mut rsl_batch_loads).cast::<[f64; 9]>() })
    }
}
