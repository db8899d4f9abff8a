//! Prints the decomposition of the closed-form test vectors of kinematics.md section 6.
//! Run: `cargo run --release --example test_vectors`.

use nalgebra::Vector3;
use rollslide::*;

fn v(x: f64, y: f64, z: f64) -> Vector3<f64> {
    Vector3::new(x, y, z)
}

fn sphere(p: Vector3<f64>, vel: Vector3<f64>, w: Vector3<f64>, r: f64) -> Sphere<f64> {
    Sphere {
        position: p,
        velocity: vel,
        angular_velocity: w,
        radius: r,
    }
}

fn show(name: &str, d: &Decomposition<f64>) {
    let f = |x: &Vector3<f64>| format!("({:+.6}, {:+.6}, {:+.6})", x.x, x.y, x.z);
    println!("{name}");
    println!("  normal rate ddot    {:+.6}", d.normal_rate);
    println!("  sliding  v_s        {}", f(&d.sliding_velocity));
    println!("  rolling  v_r        {}", f(&d.rolling_velocity));
    println!("  twisting w_tw       {:+.6}", d.twisting_rate);
    println!("  contact velocity    {}", f(&d.contact_velocity));
    println!("  tumbling w_rbr      {}", f(&d.tumbling));
    println!("  frame spin w_rbs    {:+.6}", d.frame_spin);
    println!("  rolling radius R_r  {:.6}", d.geometry.rolling_radius);
}

fn main() -> Result<(), Error> {
    let o = GeometryOptions::default();
    let all = Parts::ALL;
    let (r1, r2) = (0.7, 2.3);
    let zero = Vector3::zeros();
    let origin = zero;
    let c2 = v(3.0, 0.0, 0.0);
    let om = v(0.0, 0.0, 1.3);

    let b1 = sphere(origin, om.cross(&(origin - c2)), om * ((r1 + r2) / r1), r1);
    let b2 = sphere(c2, zero, zero, r2);
    show(
        "1. rolling without slip on a fixed sphere (expect v_r = (0, 2.99, 0))",
        &decompose_pair(&b1, &b2, o, all)?,
    );
    let legacy = legacy_rolling(&b1, &b2, o)?;
    println!(
        "  LEGACY Iwashita-Oda {:?} (differs)",
        legacy.iwashita_oda.as_slice()
    );

    let vel = v(1.7, -0.4, 0.0);
    let ball = sphere(v(0.0, 0.0, r1), vel, vel.cross(&v(0.0, 0.0, -1.0)) / r1, r1);
    let wall = Wall {
        point: zero,
        normal: v(0.0, 0.0, 1.0),
        velocity: zero,
        angular_velocity: zero,
    };
    show(
        "2. ball rolling on a fixed wall (expect v_s = 0, v_r = -V)",
        &decompose_wall(&ball, &wall, o, all)?,
    );

    let g1 = sphere(origin, zero, v(0.0, 0.0, 2.0), r1);
    let g2 = sphere(c2, zero, v(0.0, 0.0, -2.0 * r1 / r2), r2);
    show(
        "3. gear at fixed centres (expect v_r = (0, 1.4, 0))",
        &decompose_pair(&g1, &g2, o, all)?,
    );

    let s1 = sphere(origin, zero, v(0.0, 0.0, 1.0), r1);
    let s2 = sphere(c2, zero, v(0.0, 0.0, 1.0), r2);
    show(
        "4. pure sliding (expect v_r = 0, v_s = (0, 3, 0))",
        &decompose_pair(&s1, &s2, o, all)?,
    );
    println!(
        "  LEGACY Kuhn-Bagi    {:?} (reports rolling)",
        legacy_rolling(&s1, &s2, o)?.kuhn_bagi.as_slice()
    );

    let t1 = sphere(origin, zero, v(3.0, 0.0, 0.0), r1);
    let t2 = sphere(c2, zero, v(-1.0, 0.0, 0.0), r2);
    show(
        "5. pure twist (expect w_tw = 4, w_rbs = 1)",
        &decompose_pair(&t1, &t2, o, all)?,
    );

    let n = v(0.0, 0.6, 0.8);
    let p1 = v(1.0, 2.0, 3.0);
    let a = sphere(p1, v(0.3, -0.2, 0.1), v(1.0, -2.0, 0.5), 1.0);
    let b = sphere(p1 + n * 1.49, v(-0.1, 0.4, 0.2), v(0.2, 0.3, -1.0), 0.5);
    show(
        "6. general motion, midplane rule",
        &decompose_pair(&a, &b, o, all)?,
    );
    Ok(())
}
