//! The batch kernels' choice and CPU dispatch: the SIMD level ([`Simd`], with the CPU
//! detection), a resolved configuration ([`BatchConfig`]: precision and level), one step kernel
//! per precision, SIMD level and access (the decomposition's per prefetching choice too), and the
//! safe entries that validate a call and
//! run the kernel of its configuration ([`run_step`], [`run_history_step`], [`run_decompose`]).
//! The per-contact steps' choice of build ([`pair_steps_avx2`]) is here too. The C layer
//! (`capi::batch`) parses the C options into a [`BatchConfig`] and calls these.
//!
//! The SIMD kernels are the generic physics instantiated for the register-backed lane types of
//! `batch::x86::lanes` (one zmm or ymm register per value) inside `#[target_feature]` functions
//! (module `x86` here), chosen at run time from the CPU's features; `scripts/check_kernels.sh`
//! checks that the physics is inlined into them whole.

use super::history::{history_layout, HistoryLayout, Record};
#[cfg(target_arch = "x86_64")]
use super::x86::transpose::{Avx2Copy, Avx512Copy};
#[cfg(target_arch = "x86_64")]
use super::GroupCopy;
use super::{
    check_batch_model, check_time_step, decompose_kernel, step_kernel, AddSlot, BatchReport,
    DecomposeAccess, Gather, ParticleSteps, PortableCopy, StateSlot, StepAccess,
};
use crate::decompose::Parts;
use crate::error::Error;
use crate::geometry::GeometryOptions;
use crate::laws::model::Model;
use crate::layout::rsl_sphere;

/// A SIMD level of the batch kernels (the C layer takes an `RSL_SIMD_*` code to one with
/// `Simd::resolve`, which refuses a level this CPU lacks; [`Simd::available`] tells).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Simd {
    /// One contact at a time.
    Scalar,
    /// AVX2 + FMA.
    Avx2,
    /// AVX-512 F/VL/DQ/BW.
    Avx512,
}

impl Simd {
    /// Whether the running CPU supports this level.
    pub fn available(self) -> bool {
        match self {
            Simd::Scalar => true,
            #[cfg(target_arch = "x86_64")]
            Simd::Avx2 => is_x86_feature_detected!("avx2") && is_x86_feature_detected!("fma"),
            #[cfg(target_arch = "x86_64")]
            Simd::Avx512 => {
                Simd::Avx2.available()
                    && is_x86_feature_detected!("avx512f")
                    && is_x86_feature_detected!("avx512vl")
                    && is_x86_feature_detected!("avx512dq")
                    && is_x86_feature_detected!("avx512bw")
            }
            #[cfg(not(target_arch = "x86_64"))]
            _ => false,
        }
    }

    /// The widest level this CPU supports: AVX-512, then AVX2 + FMA, then scalar (the only
    /// level off x86-64). `RSL_SIMD_AUTO` takes it, for both precisions.
    pub fn best() -> Simd {
        // The widest level the CPU has, for both precisions: with the block-staged kernel the
        // AVX-512 build of the 8-lane single-precision kernel measured faster than its AVX2
        // build (in cache 27.5 against 29.3 ns per contact, full LAMMPS set); before the
        // staging it was the slower and `RSL_SIMD_AUTO` picked AVX2 for single precision.
        [Simd::Avx512, Simd::Avx2]
            .into_iter()
            .find(|s| s.available())
            .unwrap_or(Simd::Scalar)
    }
}

/// A resolved batch configuration (the C layer makes one from `rsl_batch_options` with
/// `BatchConfig::from_options`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct BatchConfig {
    /// Single (mixed) precision.
    pub f32: bool,
    /// SIMD level (available on this CPU).
    pub simd: Simd,
}

/// Whether the per-contact steps (`rsl_contact_step`, `rsl_contact_step_accumulate`) run their
/// AVX2 builds: when this CPU has AVX2 and FMA (Rust never contracts to FMA, so every build
/// gives the same bits).
///
/// A build with `--cfg rollslide_portable_pair_steps` (in `RUSTFLAGS`) always takes the
/// portable steps: `scripts/sanitizers.sh` uses one under valgrind 3.19, whose decoder rejects
/// an AVX encoding LLVM emits in some AVX2 steps (see that script).
pub fn pair_steps_avx2() -> bool {
    !cfg!(rollslide_portable_pair_steps) && Simd::Avx2.available()
}

// The step kernels, one function per (precision, SIMD level), generic over the access.

/// A state type the C kernels step: the C struct `rsl_contact_state`, or a packed history
/// record ([`Record`]), with the copiers that move its groups between memory and the block.
pub trait CState: StateSlot + Sized {
    /// The AVX2 copier.
    #[cfg(target_arch = "x86_64")]
    type Avx2: GroupCopy<rsl_sphere, Self>;
    /// The AVX-512 copier.
    #[cfg(target_arch = "x86_64")]
    type Avx512: GroupCopy<rsl_sphere, Self>;
    /// # Safety
    /// The CPU must have AVX2.
    #[cfg(target_arch = "x86_64")]
    unsafe fn avx2() -> Self::Avx2;
    /// # Safety
    /// The CPU must have AVX-512 F and DQ, and AVX2.
    #[cfg(target_arch = "x86_64")]
    unsafe fn avx512() -> Self::Avx512;
}

#[cfg(target_arch = "x86_64")]
impl<S: StateSlot> CState for S
where
    Avx2Copy: GroupCopy<rsl_sphere, S>,
    Avx512Copy: GroupCopy<rsl_sphere, S>,
{
    type Avx2 = Avx2Copy;
    type Avx512 = Avx512Copy;
    unsafe fn avx2() -> Avx2Copy {
        // SAFETY: the caller's contract is `Avx2Copy::assume`'s.
        unsafe { Avx2Copy::assume() }
    }
    unsafe fn avx512() -> Avx512Copy {
        // SAFETY: the caller's contract covers `Avx512Copy::assume`'s.
        unsafe { Avx512Copy::assume() }
    }
}

#[cfg(not(target_arch = "x86_64"))]
impl<S: StateSlot> CState for S {}

/// What the step kernels read and write: the C sphere struct and a [`CState`].
pub trait CAccess: StepAccess<P = rsl_sphere, State: CState> {}

impl<A: StepAccess<P = rsl_sphere, State: CState>> CAccess for A {}

fn scalar_f64<A: CAccess>(m: &Model, dt: f64, a: &mut A) -> BatchReport {
    step_kernel::<f64, A, _>(m, dt, a, PortableCopy)
}

fn scalar_f32<A: CAccess>(m: &Model, dt: f64, a: &mut A) -> BatchReport {
    step_kernel::<f32, A, _>(m, dt, a, PortableCopy)
}

#[cfg(target_arch = "x86_64")]
mod x86 {
    //! The SIMD kernels, one module per level and precision (and one for the decomposition):
    //! rustc puts a generic function's instances in the codegen unit of the module that defines
    //! it, so that with `codegen-units` above 1 (Cargo.toml) these families of kernels, most of
    //! the library's code, are optimised in parallel rather than all in one unit.
    pub(super) use avx2_double::avx2_f64;
    pub(super) use avx2_single::avx2_f32;
    pub(super) use avx512_double::avx512_f64;
    pub(super) use avx512_single::avx512_f32;
    pub(super) use decompose::{decompose_avx2, decompose_avx512};

    mod avx2_double {
        use super::super::*;
        use crate::batch::x86::lanes::F64x4x2;

        /// # Safety
        /// The CPU must support AVX2 and FMA.
        #[target_feature(enable = "avx2,fma")]
        pub(in crate::batch::dispatch) unsafe fn avx2_f64<A: CAccess>(
            m: &Model,
            dt: f64,
            a: &mut A,
        ) -> BatchReport {
            // Eight lanes in two ymm registers, each operation two independent instructions.
            // With four lanes in one (`F64x4`) the step took 6-19% more time on the Zen 5 host of
            // docs/performance.md (A at 1.2M contacts in both array placements, and B; 5 or 3
            // alternating runs of scripts/ab_kernels.sh: full LAMMPS set 37.9 against 33.5 ns per
            // contact, sliding 32.0 against 25.8), although it has half the register pressure:
            // likely because per step of the block it pays the slip and validity bookkeeping for
            // half as many contacts, and the clips' "any lane slips" branches are less predictable
            // over 4 lanes. (On the Zen 4 host, with the earlier kernel, the two
            // measured the same: 55.3 against 55.2 ns.)
            // SAFETY: the caller guarantees AVX2.
            step_kernel::<F64x4x2, A, _>(m, dt, a, unsafe { A::State::avx2() })
        }
    }

    mod avx2_single {
        use super::super::*;
        use crate::batch::x86::lanes::F32x8N;

        /// # Safety
        /// The CPU must support AVX2 and FMA.
        #[target_feature(enable = "avx2,fma")]
        pub(in crate::batch::dispatch) unsafe fn avx2_f32<A: CAccess>(
            m: &Model,
            dt: f64,
            a: &mut A,
        ) -> BatchReport {
            // SAFETY: the caller guarantees AVX2.
            step_kernel::<F32x8N, A, _>(m, dt, a, unsafe { A::State::avx2() })
        }
    }

    mod avx512_double {
        use super::super::*;
        use crate::batch::x86::lanes::F64x8;

        /// # Safety
        /// The CPU must support AVX-512 F/VL/DQ/BW, AVX2 and FMA.
        #[target_feature(enable = "avx512f,avx512vl,avx512dq,avx512bw,avx2,fma")]
        pub(in crate::batch::dispatch) unsafe fn avx512_f64<A: CAccess>(
            m: &Model,
            dt: f64,
            a: &mut A,
        ) -> BatchReport {
            // SAFETY: the caller guarantees AVX-512 F/DQ and AVX2.
            step_kernel::<F64x8, A, _>(m, dt, a, unsafe { A::State::avx512() })
        }
    }

    mod avx512_single {
        use super::super::*;
        use crate::batch::x86::lanes::F32x16;

        /// # Safety
        /// The CPU must support AVX-512 F/VL/DQ/BW, AVX2 and FMA.
        #[target_feature(enable = "avx512f,avx512vl,avx512dq,avx512bw,avx2,fma")]
        pub(in crate::batch::dispatch) unsafe fn avx512_f32<A: CAccess>(
            m: &Model,
            dt: f64,
            a: &mut A,
        ) -> BatchReport {
            // Sixteen lanes in one zmm (the geometry in two zmm of doubles), where the double
            // kernel has eight: against eight single lanes in a ymm (`F32x8W`) the step took 10-17%
            // less time in cache and 5-16% less at 1.2M contacts on the Zen 5 host of
            // docs/performance.md (A, alternating runs of scripts/ab_kernels.sh). Two such steps
            // fill a block of 32 contacts.
            // SAFETY: the caller guarantees AVX-512 F/DQ and AVX2.
            step_kernel::<F32x16, A, _>(m, dt, a, unsafe { A::State::avx512() })
        }
    }

    mod decompose {
        use super::super::*;
        use crate::batch::x86::lanes::{F32x8N, F32x8W, F64x4, F64x8};

        /// # Safety
        /// The CPU must support AVX2 and FMA.
        #[target_feature(enable = "avx2,fma")]
        pub(in crate::batch::dispatch) unsafe fn decompose_avx2<
            const P: bool,
            A: DecomposeAccess,
        >(
            o: GeometryOptions,
            p: Parts,
            f32: bool,
            a: &mut A,
        ) -> BatchReport {
            if f32 {
                decompose_kernel::<P, F32x8N, A>(o, p, a)
            } else {
                // Four lanes. Eight in two ymm did not pay here: on `F64x4x2` (shared with the
                // step) the step kernels compiled to different code that ran 4-7% slower in cache
                // and lost most of their full-set gain at 1.2M contacts; on a separate 8-lane type
                // (the step's code unchanged) the decomposition itself ran 9-11% slower than on
                // four lanes (A, 2,000 and 1.2M contacts, alternating runs: 21.1 against 23.0 and
                // 22.6 against 25.1 ns per contact).
                decompose_kernel::<P, F64x4, A>(o, p, a)
            }
        }

        /// # Safety
        /// The CPU must support AVX-512 F/VL/DQ/BW, AVX2 and FMA.
        #[target_feature(enable = "avx512f,avx512vl,avx512dq,avx512bw,avx2,fma")]
        pub(in crate::batch::dispatch) unsafe fn decompose_avx512<
            const P: bool,
            A: DecomposeAccess,
        >(
            o: GeometryOptions,
            p: Parts,
            f32: bool,
            a: &mut A,
        ) -> BatchReport {
            if f32 {
                // Eight lanes in a ymm. Sixteen in a zmm (`F32x16`, as the step kernels run, with
                // 16-slot rows) took 1.12x the time in cache and 1.31x at 1.2M contacts (A,
                // alternating runs: 14.4 against 16.1 and 17.8 against 23.3 ns per contact).
                decompose_kernel::<P, F32x8W, A>(o, p, a)
            } else {
                decompose_kernel::<P, F64x8, A>(o, p, a)
            }
        }
    }
}

/// Runs the kernel of `$config` (precision and SIMD level, checked available by the caller).
/// Whether it prefetches the contacts ahead is its own run-time choice
/// ([`Gather::prefetching`](crate::batch::Gather::prefetching)): one kernel per access, level
/// and precision.
macro_rules! by_kernel {
    ($config:expr, $args:tt) => {
        match ($config.simd, $config.f32) {
            (Simd::Scalar, false) => scalar_f64::<_> $args,
            (Simd::Scalar, true) => scalar_f32::<_> $args,
            #[cfg(target_arch = "x86_64")]
            // SAFETY: the caller checked `config.simd.available()`: the CPU has AVX2 and FMA.
            (Simd::Avx2, false) => unsafe { avx2_f64::<_> $args },
            #[cfg(target_arch = "x86_64")]
            // SAFETY: as above (AVX2 and FMA present).
            (Simd::Avx2, true) => unsafe { avx2_f32::<_> $args },
            #[cfg(target_arch = "x86_64")]
            // SAFETY: `available()` checked AVX-512 F/VL/DQ/BW, AVX2 and FMA.
            (Simd::Avx512, false) => unsafe { avx512_f64::<_> $args },
            #[cfg(target_arch = "x86_64")]
            // SAFETY: as above.
            (Simd::Avx512, true) => unsafe { avx512_f32::<_> $args },
            #[cfg(not(target_arch = "x86_64"))]
            _ => unreachable!("only the scalar level is available off x86-64"),
        }
    };
}

#[cfg(target_arch = "x86_64")]
use x86::{avx2_f32, avx2_f64, avx512_f32, avx512_f64};

/// Steps every contact of `access` with the kernel of `config` (safe: the SIMD level is
/// re-checked against the CPU). The model and time step are validated here; a call-level error
/// processes nothing.
pub fn run_step<A: CAccess>(
    model: &Model,
    dt: f64,
    access: &mut A,
    config: BatchConfig,
) -> Result<BatchReport, Error> {
    check_batch_model(model)?;
    check_time_step(dt)?;
    if !config.simd.available() {
        return Err(Error::InvalidArgument(
            "SIMD level not supported by this CPU".to_string(),
        ));
    }
    Ok(by_kernel!(config, (model, dt, access)))
}

/// As [`run_step`] for packed histories of `W` doubles from full-layout word `F` ([`Record`]),
/// which must be the model's [`history_layout`] (checked).
pub fn run_history_step<const W: usize, const F: usize, V: AddSlot>(
    model: &Model,
    dt: f64,
    access: &mut ParticleSteps<'_, rsl_sphere, &mut [Record<W, F>], V>,
    config: BatchConfig,
) -> Result<BatchReport, Error> {
    let layout = history_layout(model);
    if layout != (HistoryLayout { first: F, words: W }) {
        return Err(Error::InvalidArgument(format!(
            "the model's history has {} words from word {}, not {W} from {F}",
            layout.words, layout.first
        )));
    }
    run_step(model, dt, access, config)
}

/// Decomposes every contact of `access` with the kernel of `config` (safe, as [`run_step`]).
pub fn run_decompose<A: DecomposeAccess>(
    options: GeometryOptions,
    parts: Parts,
    access: &mut A,
    config: BatchConfig,
) -> Result<BatchReport, Error> {
    if !config.simd.available() {
        return Err(Error::InvalidArgument(
            "SIMD level not supported by this CPU".to_string(),
        ));
    }
    if Gather::prefetching(&*access) {
        Ok(decompose_at::<true, A>(options, parts, access, config))
    } else {
        Ok(decompose_at::<false, A>(options, parts, access, config))
    }
}

/// The decomposition kernel of `config`'s level and precision (checked available by the
/// caller), prefetching or not (`P`, as in [`run_step`]).
fn decompose_at<const P: bool, A: DecomposeAccess>(
    options: GeometryOptions,
    parts: Parts,
    access: &mut A,
    config: BatchConfig,
) -> BatchReport {
    match config.simd {
        Simd::Scalar if config.f32 => decompose_kernel::<P, f32, A>(options, parts, access),
        Simd::Scalar => decompose_kernel::<P, f64, A>(options, parts, access),
        #[cfg(target_arch = "x86_64")]
        // SAFETY: the caller checked `available()`: AVX2 and FMA.
        Simd::Avx2 => unsafe { x86::decompose_avx2::<P, A>(options, parts, config.f32, access) },
        #[cfg(target_arch = "x86_64")]
        // SAFETY: the caller checked `available()`: AVX-512 F/VL/DQ/BW, AVX2 and FMA.
        Simd::Avx512 => unsafe {
            x86::decompose_avx512::<P, A>(options, parts, config.f32, access)
        },
        #[cfg(not(target_arch = "x86_64"))]
        _ => unreachable!("only the scalar level is available off x86-64"),
    }
}
