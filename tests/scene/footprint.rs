//! The navigation grid and part footprints, against grids computed by hand.

use super::fixtures::hinged_door;
use std::collections::BTreeSet;
use std::f64::consts::FRAC_PI_2;

use kinscene::scene::nav::{
    GridBounds, NavGrid, NavGridSettings, footprint, occupancy, part_footprint,
};
use kinscene::scene::{
    BaseShape, SceneData, SceneModel, SceneModelBuilder, Shape, State, forward_kinematics,
};
use nalgebra::{Isometry3, Point2, Vector3};

/// Grid [-1, 1]² at 0.1 m: 20 × 20 cells, cell (i, j) = [-1 + 0.1 i, -1 + 0.1 (i+1)] × (same
/// in y). A door hinged at the origin (axis +z), slab x ∈ [0.01, 0.39], y ∈ [0.01, 0.03],
/// z ∈ [0, 1]; a wall x ∈ [0.7, 0.8], y ∈ [-0.5, 0.5], z ∈ [0, 1]; a floor slab below
/// z = 0 and a wall cabinet above z = 2.1, both outside the height band (0.01, 2).
fn scene() -> SceneModel {
    let mut b = SceneModelBuilder::new();
    b.nav_settings(NavGridSettings {
        resolution: 0.1,
        bounds: Some(GridBounds {
            min: Point2::new(-1.0, -1.0),
            max: Point2::new(1.0, 1.0),
        }),
        ..Default::default()
    });
    b.add_base_shape(BaseShape::new(
        "wall",
        Shape::cuboid(Vector3::new(0.05, 0.5, 0.5)),
        Isometry3::translation(0.75, 0.0, 0.5),
    ));
    b.add_base_shape(BaseShape::new(
        "floor",
        Shape::cuboid(Vector3::new(1.0, 1.0, 0.05)),
        Isometry3::translation(0.0, 0.0, -0.05),
    ));
    b.add_base_shape(BaseShape::new(
        "cabinet",
        Shape::cuboid(Vector3::new(0.3, 0.3, 0.2)),
        Isometry3::translation(-0.5, -0.5, 2.3),
    ));
    b.add_part(hinged_door(
        FRAC_PI_2,
        Vector3::new(0.19, 0.01, 0.5),
        Vector3::new(0.2, 0.02, 0.5),
    ));
    b.build().unwrap()
}

fn cells(grid: &NavGrid) -> BTreeSet<(usize, usize)> {
    grid.occupied_cells().collect()
}

#[test]
fn base_grid_holds_the_wall_only() {
    let m = scene();
    let g = m.base_grid();
    assert_eq!((g.width(), g.height()), (20, 20));
    // The wall x ∈ [0.7, 0.8] lies in column 17 and touches columns 16 and 18 (closed squares
    // count); y ∈ [-0.5, 0.5] spans rows 5..=14 and touches rows 4 and 15.
    let want: BTreeSet<_> = (16..=18)
        .flat_map(|i| (4..=15).map(move |j| (i, j)))
        .collect();
    assert_eq!(cells(g), want);
    assert_eq!(g.cell_of(Point2::new(0.75, 0.05)), Some((17, 10)));
    assert!((g.cell_center(17, 10) - Point2::new(0.75, 0.05)).norm() < 1e-12);
    assert!(g.is_occupied(25, 0), "outside the grid counts as occupied");
}

#[test]
fn an_open_door_blocks_cells_the_closed_door_does_not() {
    let m = scene();
    let door = m.part_id("door").unwrap();
    let mut data = SceneData::new(&m);
    forward_kinematics(&m, &mut data, &m.zero_state()).unwrap();
    // Closed: x ∈ [0.01, 0.39] -> columns 10..=13, y ∈ [0.01, 0.03] -> row 10.
    let closed = cells(&footprint(&m, &data).unwrap());
    assert_eq!(closed, (10..=13).map(|i| (i, 10)).collect());
    assert_eq!(cells(&part_footprint(&m, &data, door).unwrap()), closed);

    // Open 90°: (x, y) -> (-y, x): x ∈ [-0.03, -0.01] -> column 9, y ∈ [0.01, 0.39] -> rows 10..=13.
    let s = State::from_values(&m, [("hinge", FRAC_PI_2)]).unwrap();
    forward_kinematics(&m, &mut data, &s).unwrap();
    let open = cells(&footprint(&m, &data).unwrap());
    assert_eq!(open, (10..=13).map(|j| (9, j)).collect());
    assert!(open.is_disjoint(&closed));

    // Occupancy adds the base map.
    let all = occupancy(&m, &data).unwrap();
    assert_eq!(
        all.occupied_count(),
        open.len() + m.base_grid().occupied_count()
    );
}

#[test]
fn inflation_by_one_cell() {
    let mut g = NavGrid::new(Point2::new(0.0, 0.0), 0.1, 7, 7).unwrap();
    g.set_occupied(3, 3, true);
    // Neighbours' centres are 0.05 (edge) or 0.0707 (diagonal) from the square, two cells away
    // 0.15: radius 0.1 gives the 3 × 3 block.
    let grown = g.inflate(0.1).unwrap();
    let want: BTreeSet<_> = (2..=4).flat_map(|i| (2..=4).map(move |j| (i, j))).collect();
    assert_eq!(cells(&grown), want);
    // Radius 0.04 < 0.05 leaves the cell alone.
    assert_eq!(g.inflate(0.04).unwrap().occupied_count(), 1);
    assert!(g.inflate(-1.0).is_err());
}

mod properties {
    use kinscene::scene::nav::{GridBounds, NavGrid, footprint};
    use kinscene::scene::{SceneData, forward_kinematics};
    use nalgebra::Point2;
    use proptest::prelude::*;

    use super::super::generators::{scene_builder, shape_points, state};

    proptest! {
        #![proptest_config(ProptestConfig { cases: 32, ..ProptestConfig::default() })]

        /// Inflation matches its definition checked cell by cell: occupied iff the cell centre
        /// is within the radius of some occupied square.
        #[test]
        fn inflation_matches_brute_force(
            cells in prop::collection::vec(any::<bool>(), 144),
            radius in 0.0..0.5f64,
        ) {
            let mut g = NavGrid::new(Point2::new(-0.3, 0.2), 0.07, 12, 12).unwrap();
            for (k, occupied) in cells.iter().enumerate() {
                // Sparse: about one cell in eight.
                g.set_occupied(k % 12, k / 12, *occupied && k % 8 == 0);
            }
            let grown = g.inflate(radius).unwrap();
            for j in 0..12 {
                for i in 0..12 {
                    let c = g.cell_center(i, j);
                    let near = g.occupied_cells().any(|(oi, oj)| {
                        let lo = g.cell_center(oi, oj) - nalgebra::Vector2::repeat(0.035);
                        let dx = (lo.x - c.x).max(0.0).max(c.x - lo.x - 0.07);
                        let dy = (lo.y - c.y).max(0.0).max(c.y - lo.y - 0.07);
                        // 1e-12: centres and squares are rounded differently.
                        dx.hypot(dy) <= radius + 1e-12
                    });
                    let far = g.occupied_cells().all(|(oi, oj)| {
                        let lo = g.cell_center(oi, oj) - nalgebra::Vector2::repeat(0.035);
                        let dx = (lo.x - c.x).max(0.0).max(c.x - lo.x - 0.07);
                        let dy = (lo.y - c.y).max(0.0).max(c.y - lo.y - 0.07);
                        dx.hypot(dy) > radius - 1e-12
                    });
                    if near && !far {
                        // Borderline within rounding: either answer is acceptable.
                        continue;
                    }
                    prop_assert_eq!(grown.is_occupied(i, j), near, "cell ({}, {})", i, j);
                }
            }
        }

        /// Rasterisation is conservative: every sample point of a part's geometry whose
        /// height is inside the band falls in an occupied cell.
        #[test]
        fn footprints_cover_the_geometry(
            (model, q) in scene_builder(12)
                .prop_map(|mut b| {
                    b.base.nav.resolution = 0.05;
                    b.base.nav.bounds = Some(GridBounds { min: Point2::new(-3.0, -3.0), max: Point2::new(3.0, 3.0) });
                    b.build().unwrap()
                })
                .prop_flat_map(|m| { let s = state(&m); (Just(m), s) })
        ) {
            let mut data = SceneData::new(&model);
            forward_kinematics(&model, &mut data, &q).unwrap();
            let grid = footprint(&model, &data).unwrap();
            let band = model.base().nav;
            for part in model.parts() {
                let pose = data.world_from_part(part.id()).unwrap();
                for c in part.colliders() {
                    for p in shape_points(&c.shape) {
                        let w = pose * (c.part_from_shape * p);
                        if w.z > band.min_height && w.z < band.max_height {
                            if let Some((i, j)) = grid.cell_of(Point2::new(w.x, w.y)) {
                                prop_assert!(grid.is_occupied(i, j), "{} point {w} not covered", part.name());
                            }
                        }
                    }
                }
            }
        }
    }
}
