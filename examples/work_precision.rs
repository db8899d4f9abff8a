//! Run time against error of the batch configurations:
//! `cargo run --release --example work_precision` writes `docs/work_precision.md` and
//! `docs/work_precision.svg`.
//!
//! Errors, each against a reference that does not come from this library:
//! - `yade`: the decomposition of the 3940 states of `c_tests/reference/yade_mp150.csv` (a
//!   150-digit replay of YADE's algorithm), through the sign map of peers.md: normal `n`,
//!   relative spin `w1 - w2 = -relAngVel`, rolling velocity `R_r (w1 - w2) x n` with the exact
//!   rolling radius from the replay's overlap; max relative error over rows.
//! - `rolling`: sphere 1 rolling without slip around a fixed sphere 2 (kinematics.md case 1)
//!   for a quarter turn; the elastic rolling spring must equal `t v_r(t)` (closed form).
//! - `rigid`: a preloaded pair in rigid rotation about `(1, 0, 1)/sqrt(2)` for a quarter turn
//!   (models.md section 1): the sliding spring must equal the rigidly rotated initial one.
//!
//! Run time: ns/contact of the batch kernel of each configuration on 200,000 random contacts
//! (the SIMD level `RSL_SIMD_AUTO` picks, minimum of 7 calls).

use nalgebra::{Rotation3, Unit};
use rollslide::batch::dispatch::{run_decompose, run_step, BatchConfig};
use rollslide::batch::{ContactDecompose, ContactSteps, SlidingOverrides};
use rollslide::capi::batch::rsl_batch_loads;
use rollslide::capi::contact::rsl_contact_state;
use rollslide::capi::types::{rsl_sphere, rsl_vec3};
use rollslide::decompose::{Decomposition, Parts, Sphere};
use rollslide::laws::model::{Model, RollingLaw, SlidingLaw, Transport};
use rollslide::laws::step::ContactState;
use rollslide::scalar::Vec3;
use rollslide::{BranchRule, GeometryOptions, RollingRadiusRule};
use std::time::Instant;

fn rv(v: Vec3<f64>) -> rsl_vec3 {
    rsl_vec3 {
        x: v.x,
        y: v.y,
        z: v.z,
    }
}

fn sphere(p: Vec3<f64>, v: Vec3<f64>, w: Vec3<f64>, r: f64) -> rsl_sphere {
    rsl_sphere {
        position: rv(p),
        velocity: rv(v),
        angular_velocity: rv(w),
        radius: r,
    }
}

/// The kernel `RSL_SIMD_AUTO` picks for this precision.
fn config(f32: bool) -> BatchConfig {
    let options = rollslide::capi::batch::rsl_batch_options {
        precision: f32 as u32,
        ..Default::default()
    };
    BatchConfig::from_options(Some(&options)).unwrap()
}

/// One contact stepped through the batch kernel.
fn step1(
    model: &Model,
    b1: rsl_sphere,
    b2: rsl_sphere,
    dt: f64,
    s: &mut rsl_contact_state,
    f32: bool,
) {
    let (p1, p2) = ([b1], [b2]);
    let mut st = [*s];
    let mut out = [rsl_batch_loads::default()];
    let mut a = ContactSteps {
        energy: None,
        body1: &p1,
        body2: &p2,
        normal_force: &[1.0],
        normal_stiffness: None,
        states: &mut st,
        out: &mut out,
        sliding: SlidingOverrides::NONE,
    };
    let r = run_step(model, dt, &mut a, config(f32)).unwrap();
    assert_eq!(r.failed, 0, "{:?}", r.first_error);
    *s = st[0];
}

fn model(transport: Transport, geometry: GeometryOptions) -> Model {
    let mut m = Model {
        geometry,
        ..Model::default()
    };
    m.sliding.law = SlidingLaw::Linear;
    m.sliding.stiffness = 1e4;
    m.sliding.friction = f64::INFINITY;
    m.rolling.law = RollingLaw::Epsd;
    m.rolling.stiffness = 1e4;
    m.rolling.friction = f64::INFINITY;
    m.sliding_transport = transport;
    m.rolling_transport = transport;
    m
}

/// Rolling around a fixed sphere (R1 = 0.7, R2 = 2.3, Om = 1.3 z) for a quarter turn.
fn rolling_error(m: &Model, dt: f64, f32: bool) -> f64 {
    let (r1, r2, om) = (0.7, 2.3, 1.3);
    let d = r1 + r2;
    let steps = ((std::f64::consts::FRAC_PI_2 / om) / dt).round() as usize;
    let mut s = rsl_contact_state::default();
    let z = Vec3::z();
    let mut vr = Vec3::zeros();
    for k in 0..steps {
        let t = k as f64 * dt;
        let (c, sn) = ((om * t).cos(), (om * t).sin());
        let p1 = Vec3::new(-d * c, -d * sn, 0.0); // sphere 2 at the origin, n = -p1/d
        let v1 = (z * om).cross(&p1);
        let w1 = z * (om * d / r1);
        let n = -p1 / d;
        vr = (w1.cross(&n)) * (r1 * r2 / d); // R_r (w1 - w2) x n, touching: R_r = R1 R2/d
        step1(
            m,
            sphere(p1, v1, w1, r1),
            sphere(Vec3::zeros(), Vec3::zeros(), Vec3::zeros(), r2),
            dt,
            &mut s,
            f32,
        );
    }
    let xi = ContactState::from(&s).rolling_spring;
    let exact = vr * (steps as f64 * dt);
    (xi - exact).norm() / exact.norm()
}

/// Rigid rotation of a preloaded pair (R1 = 1, R2 = 0.5, delta = 0.01) about (1, 0, 1)/sqrt 2.
fn rigid_error(m: &Model, dt: f64, f32: bool) -> f64 {
    let axis = Unit::new_normalize(Vec3::new(1.0, 0.0, 1.0));
    let w = axis.into_inner();
    let (r1, r2) = (1.0, 0.5);
    let d = r1 + r2 - 0.01;
    let n0 = Vec3::new(0.0, 1.0, 0.0);
    let (p1, p2) = (Vec3::zeros(), n0 * d);
    // history at 45 degrees to the tumbling axis, tangent to n0
    let xi0 = Vec3::new(1.0, 0.0, 1.0).normalize().cross(&n0).normalize() * 1e-3
        + Vec3::new(1.0, 0.0, 0.0) * 1e-3;
    let xi0 = xi0 - n0 * xi0.dot(&n0);
    let mut s = rsl_contact_state {
        sliding_spring: rv(xi0),
        previous_normal: rv(n0),
        ..Default::default()
    };
    let steps = (std::f64::consts::FRAC_PI_2 / dt).round() as usize;
    for k in 1..=steps {
        let rot = Rotation3::from_axis_angle(&axis, k as f64 * dt);
        let (q1, q2) = (rot * p1, rot * p2);
        step1(
            m,
            sphere(q1, w.cross(&q1), w, r1),
            sphere(q2, w.cross(&q2), w, r2),
            dt,
            &mut s,
            f32,
        );
    }
    let exact = Rotation3::from_axis_angle(&axis, steps as f64 * dt) * xi0;
    (ContactState::from(&s).sliding_spring - exact).norm() / exact.norm()
}

struct YadeRow {
    b1: rsl_sphere,
    b2: rsl_sphere,
    n: Vec3<f64>,
    dw: Vec3<f64>,
    vr: Vec3<f64>,
}

fn yade_rows() -> Vec<YadeRow> {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/c_tests/reference/yade_mp150.csv"
    );
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let head: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |name: &str| head.iter().position(|h| *h == name).unwrap();
    let v3 = |f: &[f64], base: &str| {
        Vec3::new(
            f[col(&format!("{base}_x"))],
            f[col(&format!("{base}_y"))],
            f[col(&format!("{base}_z"))],
        )
    };
    lines
        .map(|l| {
            let f: Vec<f64> = l
                .split(',')
                .map(|x| x.parse().unwrap_or(f64::NAN))
                .collect();
            let (r1, r2) = (f[col("r1")], f[col("r2")]);
            let n = v3(&f, "n");
            let dw = -v3(&f, "relangvel");
            let pen = f[col("pen")];
            let (l1, l2) = (r1 - pen / 2.0, r2 - pen / 2.0);
            YadeRow {
                b1: sphere(v3(&f, "x1"), v3(&f, "v1"), v3(&f, "w1"), r1),
                b2: sphere(v3(&f, "x2"), v3(&f, "v2"), v3(&f, "w2"), r2),
                n,
                dw,
                vr: dw.cross(&n) * (l1 * l2 / (l1 + l2)),
            }
        })
        .collect()
}

fn yade_error(rows: &[YadeRow], geometry: GeometryOptions, f32: bool) -> f64 {
    let b1: Vec<rsl_sphere> = rows.iter().map(|r| r.b1).collect();
    let b2: Vec<rsl_sphere> = rows.iter().map(|r| r.b2).collect();
    let mut out = vec![zero_decomposition(); rows.len()];
    let mut a = ContactDecompose {
        body1: &b1,
        body2: &b2,
        out: &mut out,
    };
    let r = run_decompose(geometry, Parts::ALL, &mut a, config(f32)).unwrap();
    assert_eq!(r.failed, 0);
    // Relative to each row's natural scale: |w1 - w2| for the twist, R_r |w1 - w2| for v_r.
    let mut err: f64 = 0.0;
    for (row, d) in rows.iter().zip(&out) {
        let g = &d.geometry;
        err = err.max((g.normal - row.n).norm());
        let dw = row.dw.norm();
        if dw > 0.0 {
            err = err.max((d.rolling_velocity - row.vr).norm() / (g.rolling_radius * dw));
            let tw = row.dw.dot(&row.n);
            err = err.max((d.twisting_rate - tw).abs() / dw);
        }
    }
    err
}

fn zero_decomposition() -> Decomposition<f64> {
    let s = Sphere {
        position: Vec3::zeros(),
        velocity: Vec3::zeros(),
        angular_velocity: Vec3::zeros(),
        radius: 1.0,
    };
    let mut t = s;
    t.position.x = 1.5;
    rollslide::decompose_pair_unchecked(&s, &t, GeometryOptions::default(), Parts(0))
}

/// ns/contact of a configuration on 200,000 random overlapping contacts (minimum of 7 calls:
/// the least disturbed one on a shared machine).
fn time_step(m: &Model, f32: bool) -> f64 {
    let n = 200_000;
    let mut seed = 1u64;
    let mut u = || {
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    };
    let mut b1 = Vec::with_capacity(n);
    let mut b2 = Vec::with_capacity(n);
    let mut st = Vec::with_capacity(n);
    for _ in 0..n {
        let p = Vec3::new(u(), u(), u()) * 100.0;
        let dir = Vec3::new(u(), u(), u()).normalize();
        b1.push(sphere(
            p,
            Vec3::new(u(), u(), u()),
            Vec3::new(u(), u(), u()),
            0.5,
        ));
        b2.push(sphere(
            p + dir * 0.99,
            Vec3::new(u(), u(), u()),
            Vec3::new(u(), u(), u()),
            0.5,
        ));
        let tilt = (dir + Vec3::new(u(), u(), u()) * 1e-3).normalize();
        st.push(rsl_contact_state {
            previous_normal: rv(tilt),
            ..Default::default()
        });
    }
    let fn_ = vec![1.0; n];
    let mut out = vec![rsl_batch_loads::default(); n];
    let mut times = Vec::new();
    for _ in 0..7 {
        let mut states = st.clone();
        let mut a = ContactSteps {
            energy: None,
            body1: &b1,
            body2: &b2,
            normal_force: &fn_,
            normal_stiffness: None,
            states: &mut states,
            out: &mut out,
            sliding: SlidingOverrides::NONE,
        };
        let t0 = Instant::now();
        run_step(m, 1e-4, &mut a, config(f32)).unwrap();
        times.push(t0.elapsed().as_secs_f64() * 1e9 / n as f64);
    }
    times.iter().cloned().fold(f64::MAX, f64::min)
}

fn time_decompose(rows: &[YadeRow], geometry: GeometryOptions, f32: bool) -> f64 {
    let b1: Vec<rsl_sphere> = rows.iter().map(|r| r.b1).cycle().take(200_000).collect();
    let b2: Vec<rsl_sphere> = rows.iter().map(|r| r.b2).cycle().take(200_000).collect();
    let mut out = vec![zero_decomposition(); b1.len()];
    let mut times = Vec::new();
    for _ in 0..7 {
        let mut a = ContactDecompose {
            body1: &b1,
            body2: &b2,
            out: &mut out,
        };
        let t0 = Instant::now();
        run_decompose(geometry, Parts::ALL, &mut a, config(f32)).unwrap();
        times.push(t0.elapsed().as_secs_f64() * 1e9 / b1.len() as f64);
    }
    times.iter().cloned().fold(f64::MAX, f64::min)
}

/// kinematics.md section 7: |w| = 1e4, |w1 - w2| = 1e-3; relative error of v_r.
fn cancellation_error(f32: bool) -> f64 {
    let big = Vec3::new(6e3, -8e3, 0.0);
    let dw = Vec3::new(0.0, 3e-4, 1e-3 * 0.9539392014169456);
    let b1 = sphere(Vec3::zeros(), Vec3::zeros(), big + dw * 0.5, 1.0);
    let b2 = sphere(
        Vec3::new(1.99, 0.0, 0.0),
        Vec3::zeros(),
        big - dw * 0.5,
        1.0,
    );
    let mut out = vec![zero_decomposition(); 1];
    let mut a = ContactDecompose {
        body1: &[b1],
        body2: &[b2],
        out: &mut out,
    };
    run_decompose(GeometryOptions::default(), Parts::ALL, &mut a, config(f32)).unwrap();
    let n = Vec3::x();
    let (l1, l2) = (0.995, 0.995);
    let exact = dw.cross(&n) * (l1 * l2 / (l1 + l2));
    (out[0].rolling_velocity - exact).norm() / exact.norm()
}

struct Point {
    test: &'static str,
    label: String,
    ns: f64,
    err: f64,
}

fn main() {
    let exact = GeometryOptions::default();
    let approx = GeometryOptions {
        branch_rule: BranchRule::Radii,
        rolling_radius: RollingRadiusRule::Effective,
    };
    let mut pts = Vec::new();
    let rows = yade_rows();
    for f32 in [false, true] {
        let p = if f32 { "f32" } else { "f64" };
        for (gname, g) in [("exact", exact), ("radii+R_eff", approx)] {
            pts.push(Point {
                test: "yade",
                label: format!("{p} decompose {gname}"),
                ns: time_decompose(&rows, g, f32),
                err: yade_error(&rows, g, f32),
            });
        }
        pts.push(Point {
            test: "cancel",
            label: format!("{p} decompose w=1e4 dw=1e-3"),
            ns: time_decompose(&rows, exact, f32),
            err: cancellation_error(f32),
        });
        for (tname, t) in [
            ("exact", Transport::Exact),
            ("project_rescale", Transport::ProjectRescale),
            ("first_order", Transport::FirstOrder),
            ("project", Transport::Project),
            ("none", Transport::None),
        ] {
            let m = model(t, exact);
            let ns = time_step(&m, f32);
            for dt in [1e-2, 1e-3, 1e-4] {
                pts.push(Point {
                    test: "rolling",
                    label: format!("{p} {tname} dt={dt:e}"),
                    ns,
                    err: rolling_error(&m, dt, f32),
                });
                pts.push(Point {
                    test: "rigid",
                    label: format!("{p} {tname} alpha={dt:e}"),
                    ns,
                    err: rigid_error(&m, dt, f32),
                });
            }
        }
    }
    let cpu = std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|s| {
            s.lines()
                .find(|l| l.starts_with("model name"))
                .map(|l| l.split(':').nth(1).unwrap().trim().to_string())
        })
        .unwrap_or_default();
    let mut md = format!(
        "# Work against precision\n\n\
         For: users choosing a transport, branch rule or precision by its run time and its error.\n\
         Read after docs/performance.md, *Run time against error*: this page lists every point.\n\n\
         Generated by `cargo run --release --example work_precision` on {cpu} \
         (SIMD level: f64 {:?}, f32 {:?}). Run time: batch kernel, contact-major, 200,000 contacts, minimum of 7 calls. \
         Errors: relative, see the example's header for each reference.\n\n\
         | test | configuration | ns/contact | error |\n|---|---|---:|---:|\n",
        config(false).simd,
        config(true).simd
    );
    for p in &pts {
        md += &format!(
            "| {} | {} | {:.1} | {:.2e} |\n",
            p.test, p.label, p.ns, p.err
        );
    }
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/docs");
    std::fs::create_dir_all(dir).unwrap();
    std::fs::write(format!("{dir}/work_precision.md"), &md).unwrap();
    std::fs::write(format!("{dir}/work_precision.svg"), svg(&pts)).unwrap();
    println!("{md}");
}

/// The marker shapes of the plot.
#[derive(Clone, Copy)]
enum Shape {
    Circle,
    Square,
    Triangle,
    Diamond,
}

/// One marker, open, in colour `c`, centred at (x, y); `size` is the circle's radius, the
/// square's half side, the triangle's and the diamond's half height. `dot`: a filled dot in the
/// middle. The points and the legend keys are both drawn by this function, so the keys show the
/// shapes the points have.
fn marker(shape: Shape, x: f64, y: f64, size: f64, c: &str, dot: bool) -> String {
    let stroke = format!("fill=\"none\" stroke=\"{c}\" stroke-width=\"1.5\"");
    let mut s = match shape {
        Shape::Circle => format!("<circle cx=\"{x}\" cy=\"{y}\" r=\"{size}\" {stroke}/>"),
        Shape::Square => format!(
            "<rect x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\" {stroke}/>",
            x - size,
            y - size,
            2.0 * size,
            2.0 * size
        ),
        // Apex up, base below the centre (as the triangles have always been drawn).
        Shape::Triangle => format!(
            "<path d=\"M{x} {} l{} {} l{} 0 z\" {stroke}/>",
            y - size,
            size,
            size * 10.0 / 6.0,
            -2.0 * size
        ),
        Shape::Diamond => format!(
            "<path d=\"M{x} {} l{size} {size} l{} {size} l{} {} z\" {stroke}/>",
            y - size,
            -size,
            -size,
            -size
        ),
    };
    if dot {
        s += &format!("<circle cx=\"{x}\" cy=\"{y}\" r=\"1.5\" fill=\"{c}\"/>");
    }
    s
}

/// A log-log scatter plot: error (floored at 1e-17) against ns/contact. Transport tests
/// (`rolling`, `rigid`): one colour per transport, circles for f64 and squares for f32, the size
/// for dt (or alpha), a dot inside for `rigid`; decomposition tests: triangles (`yade`) and
/// diamonds (`cancel`), in black. The legend draws each key with the same marker function.
fn svg(pts: &[Point]) -> String {
    let (w, h, ml, mb, mt, mr) = (980.0, 600.0, 80.0, 60.0, 40.0, 330.0);
    let xs: Vec<f64> = pts.iter().map(|p| p.ns.log10()).collect();
    let lo = xs.iter().cloned().fold(f64::MAX, f64::min);
    let hi = xs.iter().cloned().fold(f64::MIN, f64::max);
    let (x0, x1) = (
        (lo * 5.0).floor() / 5.0,
        ((hi * 5.0).ceil() / 5.0).max(lo + 0.2),
    );
    let (y0, y1) = (-17.0, 1.0);
    let px = |x: f64| ml + (x - x0) / (x1 - x0) * (w - ml - mr);
    let py = |y: f64| mt + (y1 - y.clamp(y0, y1)) / (y1 - y0) * (h - mt - mb);
    let mut s = format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{w}\" height=\"{h}\" font-family=\"sans-serif\" font-size=\"12\">\n<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n"
    );
    s += &format!("<text x=\"{}\" y=\"22\" font-size=\"16\">rollslide batch kernels: error against run time</text>\n", ml);
    for e in (y0 as i32)..=(y1 as i32) {
        let y = py(e as f64);
        s += &format!("<line x1=\"{ml}\" x2=\"{}\" y1=\"{y}\" y2=\"{y}\" stroke=\"#ddd\"/>\n<text x=\"{}\" y=\"{}\" text-anchor=\"end\">1e{e}</text>\n", w - mr, ml - 6.0, y + 4.0);
    }
    for decade in [1.0, 10.0, 100.0, 1000.0] {
        for m in [1.0, 1.5, 2.0, 2.5, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0] {
            let v: f64 = decade * m;
            let x = v.log10();
            if x < x0 - 1e-9 || x > x1 + 1e-9 {
                continue;
            }
            let gx = px(x);
            s += &format!("<line x1=\"{gx}\" x2=\"{gx}\" y1=\"{mt}\" y2=\"{}\" stroke=\"#eee\"/>\n<text x=\"{gx}\" y=\"{}\" text-anchor=\"middle\">{v}</text>\n", h - mb, h - mb + 16.0);
        }
    }
    s += &format!("<text x=\"{}\" y=\"{}\" text-anchor=\"middle\">ns per contact (batch kernel, log scale)</text>\n", (ml + w - mr) / 2.0, h - 18.0);
    s += &format!("<text x=\"18\" y=\"{}\" transform=\"rotate(-90 18 {})\" text-anchor=\"middle\">relative error (log scale; 1e-17 = exact)</text>\n", (mt + h - mb) / 2.0, (mt + h - mb) / 2.0);
    let colour = |p: &Point| {
        let t = ["exact", "project_rescale", "first_order", "project", "none"]
            .iter()
            .position(|t| p.label.contains(&format!(" {t} ")))
            .unwrap_or(5);
        [
            "#1b9e77", "#d95f02", "#7570b3", "#e7298a", "#666666", "#000000",
        ][t]
    };
    for p in pts {
        let (x, y) = (px(p.ns.log10()), py(p.err.max(1e-17).log10()));
        let c = colour(p);
        let dtmark = if p.label.contains("1e-2") {
            7.0
        } else if p.label.contains("1e-3") {
            5.0
        } else {
            3.5
        };
        let m = if p.test == "cancel" {
            marker(Shape::Diamond, x, y, 6.0, "#000", false)
        } else if p.test == "yade" {
            marker(Shape::Triangle, x, y, 6.0, c, false)
        } else if p.label.starts_with("f32") {
            marker(Shape::Square, x, y, dtmark, c, p.test == "rigid")
        } else {
            marker(Shape::Circle, x, y, dtmark, c, p.test == "rigid")
        };
        s += &format!(
            "{m}<title>{} {}: {:.1} ns, {:.2e}</title>\n",
            p.test, p.label, p.ns, p.err
        );
    }
    // Legend: each key is drawn with the markers of the points it describes.
    let lx = w - mr + 15.0;
    let key = |k: f64| lx + 8.0 + 16.0 * k;
    let black = "#000000";
    let mut rows: Vec<(String, &str)> = [
        ("#1b9e77", "transport exact"),
        ("#d95f02", "project_rescale (LAMMPS)"),
        ("#7570b3", "first_order (YADE)"),
        ("#e7298a", "project (LIGGGHTS)"),
        ("#666666", "none"),
    ]
    .iter()
    .map(|&(c, t)| {
        (
            marker(Shape::Circle, key(0.0), 0.0, 5.0, c, false)
                + &marker(Shape::Square, key(1.0), 0.0, 5.0, c, false),
            t,
        )
    })
    .collect();
    rows.push((
        marker(Shape::Circle, key(0.0), 0.0, 5.0, black, false),
        "f64 (transport tests)",
    ));
    rows.push((
        marker(Shape::Square, key(0.0), 0.0, 5.0, black, false),
        "f32 (transport tests)",
    ));
    rows.push((
        marker(Shape::Circle, key(0.0), 0.0, 7.0, black, false)
            + &marker(Shape::Circle, key(1.0), 0.0, 5.0, black, false)
            + &marker(Shape::Circle, key(1.85), 0.0, 3.5, black, false),
        "dt (alpha) 1e-2, 1e-3, 1e-4",
    ));
    rows.push((
        marker(Shape::Circle, key(0.0), 0.0, 5.0, black, false),
        "no dot: rolling closed form",
    ));
    rows.push((
        marker(Shape::Circle, key(0.0), 0.0, 5.0, black, true),
        "dot: rigid rotation test",
    ));
    rows.push((
        marker(Shape::Triangle, key(0.0), 0.0, 6.0, black, false),
        "decomposition vs YADE mp150",
    ));
    rows.push((
        marker(Shape::Diamond, key(0.0), 0.0, 6.0, black, false),
        "decomposition, |w|=1e4, |dw|=1e-3",
    ));
    for (i, (m, t)) in rows.iter().enumerate() {
        let y = mt + 20.0 + 22.0 * i as f64;
        // The keys are drawn at y = 0 and moved to their row.
        s += &format!(
            "<g transform=\"translate(0 {})\">{m}</g><text x=\"{}\" y=\"{}\">{t}</text>\n",
            y - 4.0,
            lx + 46.0,
            y
        );
    }
    s += "</svg>\n";
    s
}
