//! Invariants of the decomposition on random cases: objectivity under superposed rigid motions
//! (kinematics.md section 4), the round trip through the inverse map, the wall as the limit of
//! a sphere, the legacy measures' known defects, and the SIMD/f32 instantiations of the same
//! generic code.
//!
//! Tolerances are relative to the magnitude scale of each case, `S = max |v_k|, R_k |w_k|`
//! (after superposition): each output is a sum of O(10) rounded terms of size <= S (times
//! d/R_r <= 40 for the inverse), so errors are a small multiple of eps S. The bounds below are
//! a few times the worst ratio measured over the seeds used (printed with --nocapture:
//! 2.1 eps S for objectivity, 2.2 eps S for the round trip, 0.8 eps S for walls).

mod common;
use common::*;
use nalgebra::Vector3;
use rollslide::*;

const EPS: f64 = f64::EPSILON;

fn random_pair(rng: &mut Rng) -> (Sphere<f64>, Sphere<f64>) {
    let r1 = rng.uniform(0.1, 3.0);
    let r2 = rng.uniform(0.1, 3.0);
    let overlap = rng.uniform(0.0, 0.2) * r1.min(r2);
    let n = rng.unit();
    let p1 = rng.vec(10.0);
    let b1 = Sphere {
        position: p1,
        velocity: rng.vec(1.0),
        angular_velocity: rng.vec(2.0),
        radius: r1,
    };
    let b2 = Sphere {
        position: p1 + n * (r1 + r2 - overlap),
        velocity: rng.vec(1.0),
        angular_velocity: rng.vec(2.0),
        radius: r2,
    };
    (b1, b2)
}

fn scale_of(spheres: &[&Sphere<f64>]) -> f64 {
    spheres
        .iter()
        .map(|s| s.velocity.norm().max(s.radius * s.angular_velocity.norm()))
        .fold(0.0, f64::max)
}

fn superpose(s: &mut Sphere<f64>, u: &Vector3<f64>, w: &Vector3<f64>, x0: &Vector3<f64>) {
    s.velocity += u + w.cross(&(s.position - x0));
    s.angular_velocity += w;
}

fn all_options() -> [GeometryOptions; 2] {
    [
        GeometryOptions::default(),
        GeometryOptions {
            branch_rule: BranchRule::Midplane,
            rolling_radius: RollingRadiusRule::Effective,
        },
    ]
}

#[test]
fn objective_parts_do_not_change_under_superposed_rigid_motion() {
    let mut rng = Rng::new(0x5eed_0001);
    let mut worst = 0.0f64;
    for _ in 0..500 {
        let (b1, b2) = random_pair(&mut rng);
        let (u, w, x0) = (rng.vec(5.0), rng.vec(5.0), rng.vec(10.0));
        let (mut c1, mut c2) = (b1, b2);
        superpose(&mut c1, &u, &w, &x0);
        superpose(&mut c2, &u, &w, &x0);
        let s = scale_of(&[&b1, &b2, &c1, &c2]);
        for o in all_options() {
            let d0 = decompose_pair(&b1, &b2, o, Parts::ALL).unwrap();
            let d1 = decompose_pair(&c1, &c2, o, Parts::ALL).unwrap();
            let errs = [
                (d1.normal_rate - d0.normal_rate).abs(),
                (d1.sliding_velocity - d0.sliding_velocity).norm(),
                (d1.rolling_velocity - d0.rolling_velocity).norm(),
                (d1.twisting_rate - d0.twisting_rate).abs() * b1.radius.max(b2.radius),
                (d1.objective_velocity1 - d0.objective_velocity1).norm(),
                (d1.objective_velocity2 - d0.objective_velocity2).norm(),
            ];
            for e in errs {
                worst = worst.max(e / (EPS * s));
            }
            let n = d0.geometry.normal;
            let wt = w - n * w.dot(&n);
            assert_vec_close(
                &(d1.tumbling - d0.tumbling),
                &wt,
                64.0 * EPS * s,
                0.0,
                "w_rbr + W_t",
            );
        }
    }
    println!("objectivity: worst error = {worst:.1} eps S");
    assert!(
        worst < 16.0,
        "objectivity error {worst} eps S exceeds 16 eps S"
    );
}

#[test]
fn non_objective_definitions_fail_by_the_stated_amounts() {
    let mut rng = Rng::new(0x5eed_0002);
    for _ in 0..200 {
        let (b1, b2) = random_pair(&mut rng);
        let (u, w, x0) = (rng.vec(5.0), rng.vec(5.0), rng.vec(10.0));
        let (mut c1, mut c2) = (b1, b2);
        superpose(&mut c1, &u, &w, &x0);
        superpose(&mut c2, &u, &w, &x0);
        let s = scale_of(&[&b1, &b2, &c1, &c2]);
        let tol = 64.0 * EPS * s;
        let radii = GeometryOptions {
            branch_rule: BranchRule::Radii,
            rolling_radius: RollingRadiusRule::Exact,
        };
        let d0 = decompose_pair(&b1, &b2, radii, Parts::ALL).unwrap();
        let d1 = decompose_pair(&c1, &c2, radii, Parts::ALL).unwrap();
        let n = d0.geometry.normal;
        let delta = d0.geometry.overlap;
        // Sliding with radii branches changes by delta W x n.
        assert_vec_close(
            &(d1.sliding_velocity - d0.sliding_velocity),
            &(w.cross(&n) * delta),
            tol,
            0.0,
            "radii v_s defect",
        );
        let l0 = legacy_rolling(&b1, &b2, GeometryOptions::default()).unwrap();
        let l1 = legacy_rolling(&c1, &c2, GeometryOptions::default()).unwrap();
        // Iwashita-Oda changes by (R1 - R2)/2 W x n.
        assert_vec_close(
            &(l1.iwashita_oda - l0.iwashita_oda),
            &(w.cross(&n) * ((b1.radius - b2.radius) / 2.0)),
            tol,
            0.0,
            "Iwashita-Oda defect",
        );
        // Kuhn-Bagi is objective but equals v_r + (R1 - R2)/(2 (R1 + R2)) v_s exactly when the
        // spheres touch; check on the objective default decomposition.
        assert_vec_close(
            &l1.kuhn_bagi,
            &l0.kuhn_bagi,
            tol,
            0.0,
            "Kuhn-Bagi objective",
        );
    }
}

#[test]
fn kuhn_bagi_reports_rolling_in_pure_sliding_of_unequal_spheres() {
    // Touching spheres (delta = 0), equal spins, fixed centres: pure sliding.
    let mut rng = Rng::new(0x5eed_0003);
    for _ in 0..100 {
        let (r1, r2) = (rng.uniform(0.1, 3.0), rng.uniform(0.1, 3.0));
        let n = rng.unit();
        let w = rng.vec(2.0);
        let zero = Vector3::zeros();
        let b1 = Sphere {
            position: zero,
            velocity: zero,
            angular_velocity: w,
            radius: r1,
        };
        let b2 = Sphere {
            position: n * (r1 + r2),
            velocity: zero,
            angular_velocity: w,
            radius: r2,
        };
        let d = decompose_pair(&b1, &b2, GeometryOptions::default(), Parts::ALL).unwrap();
        let l = legacy_rolling(&b1, &b2, GeometryOptions::default()).unwrap();
        let s = 3.0 * w.norm();
        assert!(
            d.rolling_velocity.norm() <= 8.0 * EPS * s,
            "objective v_r must vanish"
        );
        let expected = d.sliding_velocity * ((r1 - r2) / (2.0 * (r1 + r2)));
        assert_vec_close(
            &l.kuhn_bagi,
            &expected,
            16.0 * EPS * s,
            0.0,
            "Kuhn-Bagi in pure sliding",
        );
    }
}

#[test]
fn round_trip_through_the_inverse_map_returns_the_inputs() {
    let mut rng = Rng::new(0x5eed_0004);
    let mut worst = 0.0f64;
    for _ in 0..500 {
        let (b1, b2) = random_pair(&mut rng);
        let s = scale_of(&[&b1, &b2]);
        for rule in [BranchRule::Midplane, BranchRule::Radii] {
            let o = GeometryOptions {
                branch_rule: rule,
                rolling_radius: RollingRadiusRule::Exact,
            };
            let d = decompose_pair(&b1, &b2, o, Parts::ALL).unwrap();
            let back = compose_pair(&d);
            let rmin = b1.radius.min(b2.radius);
            let errs = [
                (back.velocity1 - b1.velocity).norm(),
                (back.velocity2 - b2.velocity).norm(),
                (back.angular_velocity1 - b1.angular_velocity).norm() * rmin,
                (back.angular_velocity2 - b2.angular_velocity).norm() * rmin,
            ];
            for e in errs {
                worst = worst.max(e / (EPS * s));
            }
        }
    }
    println!("round trip: worst error = {worst:.1} eps S");
    assert!(
        worst < 32.0,
        "round-trip error {worst} eps S exceeds 32 eps S"
    );
}

fn random_wall(rng: &mut Rng) -> (Sphere<f64>, Wall<f64>) {
    let r1 = rng.uniform(0.1, 3.0);
    let overlap = rng.uniform(0.0, 0.2) * r1;
    let normal = rng.unit();
    let point = rng.vec(10.0);
    let along = rng.vec(3.0);
    let along = along - normal * along.dot(&normal);
    let sphere = Sphere {
        position: point + along + normal * (r1 - overlap),
        velocity: rng.vec(1.0),
        angular_velocity: rng.vec(2.0),
        radius: r1,
    };
    let wall = Wall {
        point,
        normal,
        velocity: rng.vec(1.0),
        angular_velocity: rng.vec(0.5),
    };
    (sphere, wall)
}

#[test]
fn wall_decomposition_is_objective_and_inverts() {
    let mut rng = Rng::new(0x5eed_0005);
    let mut worst = 0.0f64;
    for _ in 0..500 {
        let (s1, wall) = random_wall(&mut rng);
        let (u, w, x0) = (rng.vec(5.0), rng.vec(5.0), rng.vec(10.0));
        let mut c1 = s1;
        superpose(&mut c1, &u, &w, &x0);
        let mut cw = wall;
        cw.velocity += u + w.cross(&(wall.point - x0));
        cw.angular_velocity += w;
        // Wall velocity scale: its material velocity over the region |r - point| <= 15.
        let sw = |x: &Wall<f64>| x.velocity.norm() + 15.0 * x.angular_velocity.norm();
        let s = scale_of(&[&s1, &c1]).max(sw(&wall)).max(sw(&cw));
        let o = GeometryOptions::default();
        let d0 = decompose_wall(&s1, &wall, o, Parts::ALL).unwrap();
        let d1 = decompose_wall(&c1, &cw, o, Parts::ALL).unwrap();
        let errs = [
            (d1.normal_rate - d0.normal_rate).abs(),
            (d1.sliding_velocity - d0.sliding_velocity).norm(),
            (d1.rolling_velocity - d0.rolling_velocity).norm(),
            (d1.twisting_rate - d0.twisting_rate).abs() * s1.radius,
            (d1.objective_velocity1 - d0.objective_velocity1).norm(),
            (d1.objective_velocity2 - d0.objective_velocity2).norm(),
        ];
        for e in errs {
            worst = worst.max(e / (EPS * s));
        }
        let back = compose_wall(&d0);
        let material2 = wall.velocity
            + wall
                .angular_velocity
                .cross(&(d0.geometry.contact_point - wall.point));
        assert_vec_close(
            &back.velocity1,
            &s1.velocity,
            256.0 * EPS * s,
            0.0,
            "wall v1",
        );
        assert_vec_close(
            &(back.angular_velocity1 * s1.radius),
            &(s1.angular_velocity * s1.radius),
            256.0 * EPS * s,
            0.0,
            "wall w1",
        );
        assert_vec_close(
            &(back.wall_angular_velocity * s1.radius),
            &(wall.angular_velocity * s1.radius),
            256.0 * EPS * s,
            0.0,
            "wall w",
        );
        assert_vec_close(
            &back.wall_contact_velocity,
            &material2,
            256.0 * EPS * s,
            0.0,
            "wall material velocity",
        );
    }
    println!("wall objectivity: worst error = {worst:.1} eps S");
    assert!(
        worst < 16.0,
        "wall objectivity error {worst} eps S exceeds 16 eps S"
    );
}

#[test]
fn wall_is_the_limit_of_a_growing_sphere_moving_with_it() {
    // Body 2 = a sphere of radius R2 whose surface touches the wall plane at the contact, moving
    // rigidly with the wall. Every rate converges to the wall's as O(R1/R2).
    let mut rng = Rng::new(0x5eed_0006);
    for _ in 0..50 {
        let (s1, wall) = random_wall(&mut rng);
        let dw = decompose_wall(&s1, &wall, GeometryOptions::default(), Parts::ALL).unwrap();
        let mut errors = Vec::new();
        for big in [1e2, 1e3, 1e4] {
            let centre = s1.position - wall.normal * (s1.radius + big - dw.geometry.overlap);
            let b2 = Sphere {
                position: centre,
                velocity: wall.velocity + wall.angular_velocity.cross(&(centre - wall.point)),
                angular_velocity: wall.angular_velocity,
                radius: big,
            };
            let ds = decompose_pair(&s1, &b2, GeometryOptions::default(), Parts::ALL).unwrap();
            let e = (ds.sliding_velocity - dw.sliding_velocity).norm()
                + (ds.rolling_velocity - dw.rolling_velocity).norm()
                + (ds.normal_rate - dw.normal_rate).abs()
                + (ds.twisting_rate - dw.twisting_rate).abs() * s1.radius
                + (ds.tumbling - dw.tumbling).norm() * s1.radius
                + (ds.contact_velocity - dw.contact_velocity).norm();
            errors.push(e);
        }
        // Each 10x in R2 must cut the difference by about 10x (first-order convergence);
        // rounding (eps R2 / R1 <= 1e-11) is far below these differences.
        assert!(
            errors[1] < 0.2 * errors[0] && errors[2] < 0.2 * errors[1],
            "{errors:?}"
        );
    }
}

#[test]
fn simd_lanes_and_f32_run_the_same_generic_code() {
    use simba::simd::{SimdValue, WideF64x4};
    let mut rng = Rng::new(0x5eed_0007);
    let cases: Vec<_> = (0..4).map(|_| random_pair(&mut rng)).collect();
    let pack = |f: &dyn Fn(usize) -> f64| WideF64x4::from([f(0), f(1), f(2), f(3)]);
    let pack3 = |f: &dyn Fn(usize) -> Vector3<f64>| {
        Vector3::new(pack(&|i| f(i).x), pack(&|i| f(i).y), pack(&|i| f(i).z))
    };
    let lanes = |first: bool| Sphere {
        position: pack3(&|i| {
            if first {
                cases[i].0.position
            } else {
                cases[i].1.position
            }
        }),
        velocity: pack3(&|i| {
            if first {
                cases[i].0.velocity
            } else {
                cases[i].1.velocity
            }
        }),
        angular_velocity: pack3(&|i| {
            if first {
                cases[i].0.angular_velocity
            } else {
                cases[i].1.angular_velocity
            }
        }),
        radius: pack(&|i| {
            if first {
                cases[i].0.radius
            } else {
                cases[i].1.radius
            }
        }),
    };
    let o = GeometryOptions::default();
    let wide = decompose_pair_unchecked(&lanes(true), &lanes(false), o, Parts::ALL);
    for (i, (b1, b2)) in cases.iter().enumerate() {
        let d = decompose_pair_unchecked(b1, b2, o, Parts::ALL);
        let lane =
            |x: &Vector3<WideF64x4>| Vector3::new(x.x.extract(i), x.y.extract(i), x.z.extract(i));
        // Same operations in the same order, no fused multiply-add on either path: identical.
        assert_eq!(lane(&wide.sliding_velocity), d.sliding_velocity);
        assert_eq!(lane(&wide.rolling_velocity), d.rolling_velocity);
        assert_eq!(wide.twisting_rate.extract(i), d.twisting_rate);
        assert_eq!(lane(&wide.contact_velocity), d.contact_velocity);

        // f32: inputs O(1), so single precision keeps ~1e-6 relative to the scale S.
        let f = |s: &Sphere<f64>| Sphere {
            position: s.position.cast::<f32>(),
            velocity: s.velocity.cast::<f32>(),
            angular_velocity: s.angular_velocity.cast::<f32>(),
            radius: s.radius as f32,
        };
        let d32 = decompose_pair_unchecked(&f(b1), &f(b2), o, Parts::ALL);
        let s = scale_of(&[b1, b2]);
        // Positions up to 10 and overlaps down to ~0: the normal carries ~10 eps32 / d error.
        let tol = 1e-4 * s;
        assert_vec_close(
            &d32.rolling_velocity.cast::<f64>(),
            &d.rolling_velocity,
            tol,
            0.0,
            "f32 v_r",
        );
        assert_vec_close(
            &d32.sliding_velocity.cast::<f64>(),
            &d.sliding_velocity,
            tol,
            0.0,
            "f32 v_s",
        );
    }
}
