//! The spheres of one configuration in world coordinates, as lanes of `f32x8`, and the
//! self-collision test between them.

use nalgebra::Isometry3;
use wide::f32x8;

use super::{RobotSpheres, Sphere};
use crate::kinematics::robot::RobotCollision;

/// Slack (m) added to every sum of radii compared in `f32`: it covers the placement of the
/// spheres in `f32` (a link's rotation, translation and sphere centres rounded to `f32`, one
/// product and three sums per coordinate: a few `6e-8` relative of the coordinates' and
/// centres' magnitudes, so under 1e-5 m within 10 m of the origin) and the few operations of
/// a test, keeping the sphere tests conservative against the exact `f64` geometry.
pub const SPHERE_SLACK: f32 = 1e-4;

/// Lanes per SIMD block.
pub(super) const LANES: usize = 8;

/// Where padding lanes sit (m, every coordinate): far from any real geometry, with radius 0.
pub(super) const FAR: f32 = 1e9;

/// The robot's spheres at one configuration (world frame, `f32`), filled by
/// [`RobotSpheres::place`]: caller-owned scratch, reused across configurations.
///
/// Per link, its spheres are stored contiguously and padded to a multiple of 8 lanes with
/// far-away spheres of radius 0.
#[derive(Debug, Clone, Default)]
pub struct SphereData {
    pub(super) x: Vec<f32>,
    pub(super) y: Vec<f32>,
    pub(super) z: Vec<f32>,
    pub(super) r: Vec<f32>,
    /// Per sphere: bit 0 set on a base link, bit 1 set on a contact shape.
    pub(super) kind: Vec<u8>,
    /// Per link: first index and number of real spheres (the padded block follows).
    pub(super) links: Vec<(usize, usize)>,
}

impl SphereData {
    /// The number of real (not padding) spheres placed.
    pub fn len(&self) -> usize {
        self.links.iter().map(|l| l.1).sum()
    }

    /// Whether no sphere is placed.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// One block of 8 lanes from `start`.
    #[inline]
    pub(super) fn block(&self, start: usize) -> [f32x8; 4] {
        let lane = |v: &[f32]| f32x8::new(v[start..start + LANES].try_into().unwrap_or([FAR; 8]));
        [lane(&self.x), lane(&self.y), lane(&self.z), lane(&self.r)]
    }
}

/// The 8 lanes of `v` from `start`, `fill` where `v` ends.
#[inline]
fn lanes(v: &[f32], start: usize, fill: f32) -> f32x8 {
    match v.get(start..start + LANES) {
        Some(lanes) => f32x8::new(lanes.try_into().unwrap_or([fill; LANES])),
        None => f32x8::splat(fill),
    }
}

/// Where [`RobotSpheres::place`] puts each link's spheres, and what does not depend on the
/// poses: per link its first index (padded to [`LANES`]; one more entry, the total), and per
/// index the radius, kind and centre in the link frame (`f32`; padding lanes: radius 0,
/// kind 0, centre 0), and per block of 8 the mask of its real lanes.
#[derive(Debug, Clone, Default)]
pub(super) struct Layout {
    starts: Vec<usize>,
    r: Vec<f32>,
    kind: Vec<u8>,
    centers: [Vec<f32>; 3],
    /// Per block of 8, the centres' coordinates as lanes (from `centers`).
    blocks: Vec<[f32x8; 3]>,
    real: Vec<f32x8>,
}

impl Layout {
    /// The layout of `links` (spheres per link), `contact` (per sphere, whether it covers a
    /// contact shape) and `base_links`.
    pub(super) fn new(links: &[Vec<Sphere>], contact: &[Vec<bool>], base_links: &[usize]) -> Self {
        let mut layout = Layout {
            starts: vec![0],
            ..Layout::default()
        };
        let mut real = Vec::new();
        for (l, (spheres, contact)) in links.iter().zip(contact).enumerate() {
            let base = u8::from(base_links.contains(&l));
            for (s, &contact) in spheres.iter().zip(contact) {
                layout.r.push(s.radius as f32);
                layout.kind.push(base | (u8::from(contact) << 1));
                for (k, c) in layout.centers.iter_mut().enumerate() {
                    c.push(s.center[k] as f32);
                }
                real.push(1.0);
            }
            while layout.r.len() % LANES != 0 {
                layout.r.push(0.0);
                layout.kind.push(0);
                for c in &mut layout.centers {
                    c.push(0.0);
                }
                real.push(0.0);
            }
            layout.starts.push(layout.r.len());
        }
        layout.real = real
            .chunks(LANES)
            .map(|c| lanes(c, 0, 0.0).simd_gt(f32x8::splat(0.0)))
            .collect();
        layout.blocks = (0..layout.real.len())
            .map(|b| [0, 1, 2].map(|k| lanes(&layout.centers[k], b * LANES, 0.0)))
            .collect();
        layout
    }
}

impl RobotSpheres {
    /// Places every link's spheres at `link_poses` (world from link, as
    /// [`RobotModel::link_poses`](super::super::RobotModel::link_poses) returns) into `data`.
    /// Links without a pose (a shorter slice) get no spheres. The centres are computed in
    /// `f32`, eight at a time (their rounding is within [`SPHERE_SLACK`]).
    pub fn place(&self, link_poses: &[Isometry3<f64>], data: &mut SphereData) {
        let n = self.links.len().min(link_poses.len());
        let layout = &self.layout;
        let total = layout.starts[n];
        // Radii and kinds do not depend on the poses: copied from the layout.
        data.r.clear();
        data.r.extend_from_slice(&layout.r[..total]);
        data.kind.clear();
        data.kind.extend_from_slice(&layout.kind[..total]);
        // Every lane up to `total` is written below: the old values need no clearing.
        for v in [&mut data.x, &mut data.y, &mut data.z] {
            v.resize(total, FAR);
        }
        data.links.clear();
        let far = f32x8::splat(FAR);
        for (l, (spheres, pose)) in self.links.iter().zip(link_poses).enumerate() {
            let (start, end) = (layout.starts[l], layout.starts[l + 1]);
            let m = pose.rotation.to_rotation_matrix();
            let r: [[f32x8; 3]; 3] =
                std::array::from_fn(|i| std::array::from_fn(|j| f32x8::splat(m[(i, j)] as f32)));
            let t = pose.translation.vector.map(|v| f32x8::splat(v as f32));
            let blocks = start / LANES..end / LANES;
            for (b, (&[cx, cy, cz], &real)) in blocks.clone().zip(
                layout.blocks[blocks.clone()]
                    .iter()
                    .zip(&layout.real[blocks]),
            ) {
                let lanes = b * LANES..(b + 1) * LANES;
                for (i, out) in [&mut data.x, &mut data.y, &mut data.z]
                    .into_iter()
                    .enumerate()
                {
                    let c = r[i][0] * cx + r[i][1] * cy + r[i][2] * cz + t[i];
                    out[lanes.clone()].copy_from_slice(real.select(c, far).as_array());
                }
            }
            data.links.push((start, spheres.len()));
        }
    }

    /// The first checked link pair `(i, j)` (in the order of
    /// [`RobotSpheres::checked_pairs`]) with a sphere of `i` and a sphere of `j` within
    /// the sum of their radii plus [`SPHERE_SLACK`], or `None`. `None` means the exact
    /// geometry is free of self-collision too (the spheres cover it).
    pub fn self_collision(&self, data: &SphereData) -> Option<(usize, usize)> {
        self.checked
            .iter()
            .copied()
            .find(|&(i, j)| self.pair_meets(data, i, j))
    }

    /// Exact self-collision with the spheres as the broad phase: the first checked pair whose
    /// spheres meet ([`RobotSpheres::pair_meets`]) and whose exact shapes touch
    /// ([`RobotCollision::pair_touches`]). The same answer as
    /// [`RobotCollision::self_collision`] when `self` was built from `collision` and `data`
    /// holds the spheres placed at `link_poses` (pairs the spheres clear cannot touch).
    pub fn self_collision_exact(
        &self,
        data: &SphereData,
        collision: &RobotCollision,
        link_poses: &[Isometry3<f64>],
    ) -> Option<(usize, usize)> {
        self.checked
            .iter()
            .copied()
            .find(|&(i, j)| self.pair_meets(data, i, j) && collision.pair_touches(link_poses, i, j))
    }

    /// A lower bound (m) on the distance between the spheres of links `i` and `j` in `data`:
    /// the least over sphere pairs of centre distance minus both radii minus
    /// [`SPHERE_SLACK`] (negative where [`RobotSpheres::pair_meets`] is true;
    /// `f32::INFINITY` if either link has no spheres placed).
    pub(super) fn pair_clearance(&self, data: &SphereData, i: usize, j: usize) -> f32 {
        let (Some(&(si, ni)), Some(&(sj, nj))) = (data.links.get(i), data.links.get(j)) else {
            return f32::INFINITY;
        };
        let mut least = f32x8::splat(f32::INFINITY);
        for a in si..si + ni {
            let (ax, ay, az) = (
                f32x8::splat(data.x[a]),
                f32x8::splat(data.y[a]),
                f32x8::splat(data.z[a]),
            );
            let ar = f32x8::splat(data.r[a] + SPHERE_SLACK);
            for start in (sj..sj + nj).step_by(LANES) {
                let [bx, by, bz, br] = data.block(start);
                let (dx, dy, dz) = (bx - ax, by - ay, bz - az);
                least = least.min((dx * dx + dy * dy + dz * dz).sqrt() - br - ar);
            }
        }
        least.to_array().into_iter().fold(f32::INFINITY, f32::min)
    }

    /// Whether a sphere of link `i` and a sphere of link `j` in `data` are within the sum of
    /// their radii plus [`SPHERE_SLACK`] (`false` if either link has no spheres placed).
    pub fn pair_meets(&self, data: &SphereData, i: usize, j: usize) -> bool {
        self.pair_within(data, i, j, 0.0)
    }

    /// [`RobotSpheres::pair_meets`] with a clearance: whether a sphere of link `i` and a
    /// sphere of link `j` are within the sum of their radii plus [`SPHERE_SLACK`] plus
    /// `margin` (m). `false` means the links' exact shapes keep more than `margin` apart.
    pub(super) fn pair_within(&self, data: &SphereData, i: usize, j: usize, margin: f32) -> bool {
        let (Some(&(si, ni)), Some(&(sj, nj))) = (data.links.get(i), data.links.get(j)) else {
            return false;
        };
        let slack = f32x8::splat(SPHERE_SLACK + margin);
        for a in si..si + ni {
            let (ax, ay, az) = (
                f32x8::splat(data.x[a]),
                f32x8::splat(data.y[a]),
                f32x8::splat(data.z[a]),
            );
            let ar = f32x8::splat(data.r[a]) + slack;
            for start in (sj..sj + nj).step_by(LANES) {
                let [bx, by, bz, br] = data.block(start);
                let (dx, dy, dz) = (bx - ax, by - ay, bz - az);
                let reach = br + ar;
                if (dx * dx + dy * dy + dz * dz).simd_le(reach * reach).any() {
                    return true;
                }
            }
        }
        false
    }
}

#[cfg(test)]
mod tests {
    use nalgebra::DVector;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    use super::*;
    use crate::kinematics::robot::{RobotConfig, RobotModel, SphereSettings};

    /// The `f32` placement stays within a tenth of [`SPHERE_SLACK`] of the `f64` one (the
    /// slack's budget for it is 1e-5 m within 10 m of the origin): 500 seeded configurations
    /// of the Gen3 with its base anywhere within 7 m of the origin (arm reach included, under
    /// 10 m). Radii, kinds and padding lanes are the layout's.
    #[test]
    fn f32_placement_is_within_the_slack() {
        let robot = RobotModel::kinova_gen3_mobile();
        let collision = RobotCollision::new(&robot).unwrap();
        let spheres = RobotSpheres::new(&robot, &collision, &SphereSettings::default()).unwrap();
        let (lo, hi) = robot.arm_bounds();
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        let mut data = SphereData::default();
        let mut worst: f64 = 0.0;
        for _ in 0..500 {
            let arm = DVector::from_fn(robot.dof(), |i, _| {
                rng.random_range(lo[i].max(-3.2)..=hi[i].min(3.2))
            });
            let base = [
                rng.random_range(-5.0..5.0),
                rng.random_range(-5.0..5.0),
                rng.random_range(-3.2..3.2),
            ];
            let poses = robot.link_poses(&RobotConfig { base, arm }).unwrap();
            spheres.place(&poses, &mut data);
            assert_eq!(data.len(), spheres.count());
            for (l, (link, pose)) in spheres.links().iter().zip(&poses).enumerate() {
                let (start, n) = data.links[l];
                assert_eq!(n, link.len());
                for (k, s) in link.iter().enumerate() {
                    let c = pose * s.center;
                    let i = start + k;
                    let placed = [data.x[i], data.y[i], data.z[i]].map(f64::from);
                    for (p, e) in placed.iter().zip(c.iter()) {
                        worst = worst.max((p - e).abs());
                    }
                    assert_eq!(data.r[i], s.radius as f32);
                }
                let padded = start + n.div_ceil(LANES) * LANES;
                for i in start + n..padded {
                    assert_eq!((data.x[i], data.r[i]), (FAR, 0.0));
                }
            }
        }
        assert!(worst < f64::from(SPHERE_SLACK) / 10.0, "{worst}");
        println!("f32 placement: worst coordinate error {worst:e} m");
    }
}
