//! Time per estimate of the articulation estimators on a synthetic door interaction
//! (σ = 5 mm depth noise, 5 % outliers, ~25k points per cloud, 200 end-effector poses).
//!
//! `cargo bench --bench articulation -- --warm-up-time 1 --measurement-time 2`

use criterion::{Criterion, criterion_group, criterion_main};
use kinscene::articulation::synthetic::{DepthCamera, DepthNoise, SyntheticBox, render};
use kinscene::articulation::{
    ArticulationEstimator, Interaction, Proprioceptive, Screw, TwoView, TwoViewSettings,
};
use nalgebra::{Isometry3, Point3, Translation3, UnitQuaternion, Vector3};
use std::hint::black_box;

/// A cabinet (open box), a floor and a wall, with a 0.5 m door hinged on the left turned 40°.
fn door_scene() -> (
    Vec<SyntheticBox>,
    Vec<SyntheticBox>,
    Isometry3<f64>,
    Point3<f64>,
) {
    let b = |c: [f64; 3], h: [f64; 3], label| SyntheticBox {
        world_from_box: Isometry3::translation(c[0], c[1], c[2]),
        half_extents: Vector3::from(h),
        label,
    };
    let (w, d, h, t) = (0.5, 0.55, 0.75, 0.018);
    let statics = vec![
        b([t / 2.0, d / 2.0, h / 2.0], [t / 2.0, d / 2.0, h / 2.0], 0),
        b(
            [w - t / 2.0, d / 2.0, h / 2.0],
            [t / 2.0, d / 2.0, h / 2.0],
            0,
        ),
        b(
            [w / 2.0, d / 2.0, t / 2.0],
            [w / 2.0 - t, d / 2.0, t / 2.0],
            0,
        ),
        b(
            [w / 2.0, d / 2.0, h - t / 2.0],
            [w / 2.0 - t, d / 2.0, t / 2.0],
            0,
        ),
        b(
            [w / 2.0, d - t / 2.0, h / 2.0],
            [w / 2.0 - t, t / 2.0, h / 2.0 - t],
            0,
        ),
        b([w / 2.0, 0.0, -0.05], [1.5, 1.8, 0.05], 0),
        b([w / 2.0, d + 0.05, 1.0], [1.5, 0.05, 1.0], 0),
    ];
    let part = vec![
        b(
            [w / 2.0, -t / 2.0, h / 2.0],
            [w / 2.0 - 0.002, t / 2.0, h / 2.0 - 0.002],
            1,
        ),
        b([w - 0.06, -t - 0.025, 0.45], [0.008, 0.008, 0.06], 1),
    ];
    let motion = Screw {
        axis: -Vector3::z_axis(),
        point: Point3::new(0.0, -t, 0.0),
        angle: 40f64.to_radians(),
        translation: 0.0,
    }
    .to_isometry();
    (
        statics,
        part,
        motion,
        Point3::new(w - 0.06, -t - 0.033, 0.45),
    )
}

fn bench(c: &mut Criterion) {
    let (statics, part, motion, contact) = door_scene();
    let camera = |origin: Point3<f64>| DepthCamera {
        origin,
        target: Point3::new(0.25, 0.1, 0.375),
        up: Vector3::z(),
        horizontal_fov: 60f64.to_radians(),
        width: 200,
        height: 150,
        max_range: 4.0,
    };
    let noise = |seed| DepthNoise {
        sigma: 0.005,
        outlier_fraction: 0.05,
        seed,
    };
    let pre_boxes: Vec<_> = statics.iter().chain(&part).copied().collect();
    let post_boxes: Vec<_> = statics
        .iter()
        .copied()
        .chain(part.iter().map(|b| SyntheticBox {
            world_from_box: motion * b.world_from_box,
            ..*b
        }))
        .collect();
    let pre = render(
        &pre_boxes,
        &camera(Point3::new(0.4, -1.1, 0.83)),
        &noise(1),
        0.0,
    )
    .unwrap()
    .cloud;
    let post = render(
        &post_boxes,
        &camera(Point3::new(0.49, -1.3, 0.93)),
        &noise(2),
        1.0,
    )
    .unwrap()
    .cloud;
    let grasp = Isometry3::from_parts(
        Translation3::from(contact.coords),
        UnitQuaternion::identity(),
    );
    let ee_poses: Vec<_> = (0..200)
        .map(|k| {
            let f = k as f64 / 199.0;
            let m = Screw {
                angle: 40f64.to_radians() * f,
                ..Screw::from_isometry(&motion)
            }
            .to_isometry();
            let mut p = m * grasp;
            // Deterministic ±5 mm perturbation.
            p.translation.vector += Vector3::new(
                (k as f64 * 1.7).sin(),
                (k as f64 * 2.3).cos(),
                (k as f64 * 0.9).sin(),
            ) * 0.005;
            (0.01 * k as f64, p)
        })
        .collect();
    let interaction = Interaction {
        pre: &pre,
        post: &post,
        contact_pre: contact,
        contact_post: motion * contact,
        ee_poses: &ee_poses,
    };
    // The two-view estimator with and without the voxel thinning of its ICP points (before the
    // thinning, ICP ran on an evenly strided subset of at most 4000 part points).
    let unthinned = TwoView {
        settings: TwoViewSettings {
            icp_voxel: 0.0,
            ..TwoViewSettings::default()
        },
    };
    let estimators: Vec<(&str, Box<dyn ArticulationEstimator>)> = vec![
        ("two-view", Box::new(TwoView::default())),
        ("two-view, no voxel thinning", Box::new(unthinned)),
        ("proprioceptive", Box::new(Proprioceptive::default())),
    ];
    let mut group = c.benchmark_group("articulation");
    group.sample_size(10);
    for (name, est) in &estimators {
        group.bench_function(*name, |b| {
            b.iter(|| black_box(est.estimate(black_box(&interaction)).unwrap()))
        });
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
