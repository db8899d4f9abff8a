//! Shared helpers of the integration tests: a seeded generator and tolerance checks.
#![allow(dead_code)]

use rollslide::scalar::Vec3;

/// SplitMix64: a small, seeded, reproducible generator (no dependency needed).
pub struct Rng(u64);

impl Rng {
    pub fn new(seed: u64) -> Self {
        Rng(seed)
    }
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    /// Uniform in [lo, hi).
    pub fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        let u = (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64;
        lo + (hi - lo) * u
    }
    pub fn vec(&mut self, scale: f64) -> Vec3<f64> {
        Vec3::new(
            self.uniform(-scale, scale),
            self.uniform(-scale, scale),
            self.uniform(-scale, scale),
        )
    }
    pub fn unit(&mut self) -> Vec3<f64> {
        loop {
            let v = self.vec(1.0);
            let n = v.norm();
            if n > 0.1 && n <= 1.0 {
                return v / n;
            }
        }
    }
}

/// |a - b| <= abs + rel |b|.
pub fn close(a: f64, b: f64, abs: f64, rel: f64) -> bool {
    (a - b).abs() <= abs + rel * b.abs()
}

#[track_caller]
pub fn assert_close(a: f64, b: f64, abs: f64, rel: f64, what: &str) {
    assert!(
        close(a, b, abs, rel),
        "{what}: got {a:e}, expected {b:e} (diff {:e}, abs tol {abs:e}, rel tol {rel:e})",
        (a - b).abs()
    );
}

#[track_caller]
pub fn assert_vec_close(a: &Vec3<f64>, b: &Vec3<f64>, abs: f64, rel: f64, what: &str) {
    let diff = (a - b).norm();
    assert!(
        diff <= abs + rel * b.norm(),
        "{what}: got {a:?}, expected {b:?} (|diff| {diff:e}, abs tol {abs:e}, rel tol {rel:e})"
    );
}

pub mod reference;

pub fn v(x: f64, y: f64, z: f64) -> Vec3<f64> {
    Vec3::new(x, y, z)
}
