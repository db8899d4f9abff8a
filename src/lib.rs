//! # rollslide
//!
//! Objective contact kinematics and rolling resistance for DEM codes, after Wang,
//! Alonso-Marroquin & Guo, "Rolling and sliding in 3-D discrete element models",
//! Particuology 23 (2015) 49-55.
//!
//! For two contacting spheres (or a sphere and a flat wall) the relative motion of body 1 with
//! respect to body 2 is split into normal rate, sliding velocity, rolling velocity
//! `v_r = R_r (w1 - w2) x n` and twisting rate, plus the rigid-body parts of the pair.
//! Conventions: `n` points from body 1 to body 2; rates are body 1 relative to body 2; loads
//! are returned on body 1, with body 2's reaction given separately.
//!
//! The physics is written once, generic over [`scalar::Real`] (f64, f32 and SIMD lanes).
//! The C ABI lives in [`capi`]; its header is `include/rollslide.h`. The engine (the batch
//! kernels, their CPU dispatch, SIMD lanes and copiers) lives in [`batch`], the per-contact fast
//! path in [`laws::fast_path`], and the C structs they read in place in [`layout`].

pub mod batch;
pub mod capi;
pub mod decompose;
pub mod error;
pub mod geometry;
pub mod inverse;
pub mod laws;
pub mod layout;
pub mod legacy;
pub mod loads;
pub mod scalar;

pub use decompose::{
    decompose_pair, decompose_pair_unchecked, decompose_wall, decompose_wall_unchecked,
    Decomposition, Parts, Sphere, Wall,
};
pub use error::Error;
pub use geometry::{BranchRule, ContactGeometry, GeometryOptions, RollingRadiusRule};
pub use inverse::{compose_pair, compose_wall, PairVelocities, WallVelocities};
pub use legacy::{legacy_rolling, LegacyRolling};
pub use loads::{contact_loads, ContactLoads};
