//! Pinocchio forward kinematics and frame Jacobians on a 7-DoF Panda-like arm.
//!
//! `fk_frame/rust_api` times `forward_kinematics` + `frame_placement(tcp)` through the safe
//! Rust API (input validation, FFI call, pose conversion); `fk_frame/cpp_loop` times the same
//! work (`forwardKinematics` + `updateFramePlacement`) in a C++ loop inside the shim, in the same
//! run, so the difference is the cost of the Rust layer and the FFI crossing.
//!
//! Run: `cargo bench --bench pinocchio_fk --no-default-features --features pinocchio,bench`.

use std::f64::consts::FRAC_PI_2;
use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use kinscene_pinocchio::{
    Data, FrameIndex, JointIndex, JointKind, JointLimits, Model, ModelBuilder, ReferenceFrame,
    bench, forward_kinematics, frame_jacobian, frame_placement,
};
use nalgebra::{DVector, Isometry3, Translation3, UnitQuaternion, Vector3};

/// Franka Panda kinematics (modified DH from Franka's documentation): per joint, the
/// translation (m) and roll (rad) of `parent_from_joint`, and the position limits (rad).
const PANDA: [([f64; 3], f64, (f64, f64)); 7] = [
    ([0.0, 0.0, 0.333], 0.0, (-2.8973, 2.8973)),
    ([0.0, 0.0, 0.0], -FRAC_PI_2, (-1.7628, 1.7628)),
    ([0.0, -0.316, 0.0], FRAC_PI_2, (-2.8973, 2.8973)),
    ([0.0825, 0.0, 0.0], FRAC_PI_2, (-3.0718, -0.0698)),
    ([-0.0825, 0.384, 0.0], -FRAC_PI_2, (-2.8973, 2.8973)),
    ([0.0, 0.0, 0.0], FRAC_PI_2, (-0.0175, 3.7525)),
    ([0.088, 0.0, 0.0], FRAC_PI_2, (-2.8973, 2.8973)),
];

fn panda() -> (Model, FrameIndex) {
    let mut b = ModelBuilder::new();
    let mut parent = JointIndex::UNIVERSE;
    for (i, (t, roll, (lo, hi))) in PANDA.into_iter().enumerate() {
        let placement = Isometry3::from_parts(
            Translation3::new(t[0], t[1], t[2]),
            UnitQuaternion::from_euler_angles(roll, 0.0, 0.0),
        );
        parent = b
            .add_joint(
                &format!("panda_joint{}", i + 1),
                parent,
                placement,
                JointKind::Revolute { axis: Vector3::z() },
                JointLimits::position(lo, hi),
            )
            .expect("valid joint");
    }
    // Flange 0.107 m along z, hand rotated by -π/4, tool centre point 0.1034 m further.
    let joint7_from_tcp = Isometry3::from_parts(
        Translation3::new(0.0, 0.0, 0.107 + 0.1034),
        UnitQuaternion::from_euler_angles(0.0, 0.0, -std::f64::consts::FRAC_PI_4),
    );
    let tcp = b
        .add_frame("panda_tcp", parent, joint7_from_tcp)
        .expect("valid frame");
    (b.build().expect("the Pinocchio shim loads"), tcp)
}

fn benches(c: &mut Criterion) {
    let (model, tcp) = panda();
    let mut data = Data::new(&model).expect("data");
    let q = DVector::from_vec(vec![0.1, -0.5, 0.2, -2.0, 0.3, 1.6, 0.7]);

    let mut fk = c.benchmark_group("fk_frame");
    fk.bench_function("rust_api", |b| {
        b.iter(|| {
            forward_kinematics(&model, &mut data, black_box(&q)).expect("fk");
            black_box(frame_placement(&model, &data, tcp).expect("placement"))
        })
    });
    fk.bench_function("cpp_loop", |b| {
        b.iter_custom(|iterations| {
            bench::cpp_forward_kinematics_loop(&model, &mut data, &q, tcp, iterations)
                .expect("C++ loop")
        })
    });
    fk.finish();

    let mut jac = c.benchmark_group("frame_jacobian");
    for reference in ReferenceFrame::ALL {
        jac.bench_function(format!("{reference:?}"), |b| {
            b.iter(|| {
                frame_jacobian(&model, &mut data, black_box(&q), tcp, reference).expect("jacobian")
            })
        });
    }
    jac.finish();
}

criterion_group!(pinocchio_fk, benches);
criterion_main!(pinocchio_fk);
