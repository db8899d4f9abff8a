//! The models of LAMMPS 20220106's `pair granular` (and `fix wall/gran granular`), and the
//! coefficients the LAMMPS tests that cover every combination of them give each one.

/// Normal models.
pub const NORMAL: [&str; 5] = ["hooke", "hertz", "hertz/material", "dmt", "jkr"];
/// Normal damping models.
pub const DAMPING: [&str; 4] = ["velocity", "mass_velocity", "viscoelastic", "tsuji"];
/// Tangential (sliding) models.
pub const TANGENTIAL: [&str; 6] = [
    "linear_nohistory",
    "linear_history",
    "mindlin",
    "mindlin_rescale",
    "mindlin/force",
    "mindlin_rescale/force",
];
/// Twisting models (rolling is `sds`, its only model).
pub const TWISTING: [&str; 2] = ["marshall", "sds"];

/// One combination of the models: normal, damping, tangential, twisting (rolling sds in all).
#[derive(Clone, Copy, Debug)]
pub struct Law {
    pub normal: &'static str,
    pub damping: &'static str,
    pub tangential: &'static str,
    pub twisting: &'static str,
}

/// The scale of a scene's coefficients: Young's modulus `young` sets the normal stiffness
/// (hooke `k = young / 2`, hertz `k = 0.7 young`, close to hertz/material's `4/3 E*` with
/// Poisson's ratio 0.3), `cohesion` is dmt's and jkr's surface energy, `friction` the sliding
/// friction coefficient (rolling's is a quarter of it, sds twisting's an eighth).
#[derive(Clone, Copy, Debug)]
pub struct Scale {
    pub young: f64,
    pub cohesion: f64,
    pub friction: f64,
}

impl Law {
    /// Whether the normal model takes material properties (Young's modulus, Poisson's ratio),
    /// from which the mindlin family's NULL stiffness derives.
    pub fn material(&self) -> bool {
        matches!(self.normal, "hertz/material" | "dmt" | "jkr")
    }

    /// The `pair_coeff` (and `fix wall/gran granular`) keywords of this law at `scale`.
    ///
    /// Damping coefficients: velocity 5, mass_velocity 10, viscoelastic 100 (times the contact
    /// radius and the effective mass: about 2 at a typical contact, so that every damping model
    /// dissipates a comparable share), tsuji 0.7 (a restitution coefficient). Tangential:
    /// `linear_history` 1.5e4, the mindlin family NULL with a material normal model and 1e5
    /// (times the contact radius) otherwise, tangential damping 0.5 of the normal. Rolling sds
    /// 5e3 5; twisting sds 200 1.
    pub fn coeffs(&self, scale: &Scale) -> String {
        let e = scale.young;
        let damping = match self.damping {
            "velocity" => 5.0,
            "mass_velocity" => 10.0,
            "viscoelastic" => 100.0,
            "tsuji" => 0.7,
            d => panic!("unknown damping {d}"),
        };
        let normal = match self.normal {
            "hooke" => format!("hooke {} {damping}", e / 2.0),
            "hertz" => format!("hertz {} {damping}", 0.7 * e),
            "hertz/material" => format!("hertz/material {e} {damping} 0.3"),
            "dmt" | "jkr" => format!("{} {e} {damping} 0.3 {}", self.normal, scale.cohesion),
            n => panic!("unknown normal model {n}"),
        };
        let mu = scale.friction;
        let tangential = match self.tangential {
            "linear_nohistory" => format!("linear_nohistory 0.5 {mu}"),
            "linear_history" => format!("linear_history 1.5e4 0.5 {mu}"),
            t => format!(
                "{t} {} 0.5 {mu}",
                if self.material() { "NULL" } else { "1e5" }
            ),
        };
        let twisting = match self.twisting {
            "marshall" => "marshall".to_string(),
            "sds" => format!("sds 200 1 {}", mu / 8.0),
            t => panic!("unknown twisting model {t}"),
        };
        format!(
            "{normal} damping {} tangential {tangential} rolling sds 5e3 5 {} twisting {twisting}",
            self.damping,
            mu / 4.0
        )
    }

    /// "normal, damping, tangential, twisting".
    pub fn name(&self) -> String {
        format!(
            "{}, {}, {}, {}",
            self.normal, self.damping, self.tangential, self.twisting
        )
    }

    /// The name as a file-name part: "normal__damping__tangential__twisting", `/` as `_`.
    pub fn tag(&self) -> String {
        self.name().replace([',', ' ', '/'], "_")
    }

    /// Stock's classes to compare with. Stock 20220106 computes DMT's critical force (its
    /// limits, and its transports' thresholds) from a cohesion it never sets, so DMT is compared
    /// with stock's own classes rebuilt with it set (-DROLLSLIDE_DMT_REFERENCE=ON, which the
    /// tests' build turns on): `(pair style, wall fix)`.
    pub fn stock_styles(&self) -> (&'static str, &'static str) {
        if self.normal == "dmt" {
            ("granular/dmt_reference", "wall/gran/dmt_reference")
        } else {
            ("granular", "wall/gran")
        }
    }

    /// What `stock_styles` compares with, for a printed line: empty, or the DMT reference.
    pub fn stock_note(&self) -> &'static str {
        if self.normal == "dmt" {
            " (against stock with DMT's cohesion set)"
        } else {
            ""
        }
    }
}

/// Every combination: normal x damping x tangential x twisting (240; the LAMMPS styles accept
/// them all).
pub fn every_combination() -> Vec<Law> {
    let mut laws = Vec::new();
    for normal in NORMAL {
        for damping in DAMPING {
            for tangential in TANGENTIAL {
                for twisting in TWISTING {
                    laws.push(Law {
                        normal,
                        damping,
                        tangential,
                        twisting,
                    });
                }
            }
        }
    }
    laws
}

/// Every normal x tangential combination (30), each with one damping and one twisting model,
/// in turn along both lists: each normal model meets all four damping models and both
/// twisting models, each tangential model at least three damping models and both twisting
/// models; except that linear_nohistory always takes sds (stock's Marshall twisting takes its
/// stiffness from the sliding spring's, none with linear_nohistory, and divides by it where
/// the twisting moment reaches its limit: NaN).
pub fn normal_by_tangential() -> Vec<Law> {
    let mut laws = Vec::new();
    for (i, normal) in NORMAL.into_iter().enumerate() {
        for (j, tangential) in TANGENTIAL.into_iter().enumerate() {
            let twisting = if tangential == "linear_nohistory" {
                "sds"
            } else {
                TWISTING[(i + j) % TWISTING.len()]
            };
            laws.push(Law {
                normal,
                damping: DAMPING[(i + j) % DAMPING.len()],
                tangential,
                twisting,
            });
        }
    }
    laws
}

/// Runs `job` on every item of `items` on `threads` threads (the LAMMPS runs of a matrix are
/// independent processes), returning the results in the items' order.
pub fn parallel_map<T: Sync, R: Send>(
    items: &[T],
    threads: usize,
    job: impl Fn(&T) -> R + Sync,
) -> Vec<R> {
    let next = std::sync::atomic::AtomicUsize::new(0);
    let results: Vec<std::sync::Mutex<Option<R>>> =
        items.iter().map(|_| std::sync::Mutex::new(None)).collect();
    std::thread::scope(|s| {
        for _ in 0..threads.max(1) {
            s.spawn(|| loop {
                let k = next.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                if k >= items.len() {
                    break;
                }
                let r = job(&items[k]);
                *results[k].lock().unwrap() = Some(r);
            });
        }
    });
    results
        .into_iter()
        .map(|m| m.into_inner().unwrap().expect("every item ran"))
        .collect()
}
