//! The static base map B: fixed collision geometry and navigation-grid settings.

use nalgebra::Isometry3;
use serde::{Deserialize, Serialize};

use super::nav::NavGridSettings;
use super::shape::{BoundingSphere, Shape};

/// One static shape of the base map (a wall, a counter, a carcass), in the world frame.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct BaseShape {
    /// Name, unique among base shapes (for allowed-collision sets and reports).
    pub name: String,
    /// The shape.
    pub shape: Shape,
    /// Pose of the shape frame in the world frame.
    pub world_from_shape: Isometry3<f64>,
}

impl BaseShape {
    /// A named static shape at `world_from_shape`.
    pub fn new(name: impl Into<String>, shape: Shape, world_from_shape: Isometry3<f64>) -> Self {
        BaseShape {
            name: name.into(),
            shape,
            world_from_shape,
        }
    }

    /// The shape's bounding sphere in the world frame.
    pub fn bounding_sphere(&self) -> BoundingSphere {
        let s = self.shape.bounding_sphere();
        BoundingSphere {
            center: self.world_from_shape * s.center,
            radius: s.radius,
        }
    }
}

/// The static scene: collision shapes in the world frame (z up, REP 103) and the settings of
/// the navigation grid derived from them.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct BaseMap {
    /// Name of the static base (for URDF, the root link), kept for export.
    pub name: Option<String>,
    /// Static collision shapes.
    pub shapes: Vec<BaseShape>,
    /// How the 2D navigation grid is derived from the shapes.
    pub nav: NavGridSettings,
}
