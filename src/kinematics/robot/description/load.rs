//! Loading a [`RobotModel`] from a [`RobotDescription`]: resolve the paths, load the URDF with
//! the options, take the SRDF, set the stow, the exemptions and the base.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use nalgebra::DVector;

use super::paths::{Variables, resolve, resolve_file};
use super::{BaseDescription, RobotDescription};
use crate::kinematics::robot::{
    BaseKind, PairSampling, RobotCollision, RobotConfig, RobotError, RobotImportOptions,
    RobotModel, Srdf, StowSearch,
};

/// The description's files and import options, paths resolved.
struct Resolved {
    urdf: PathBuf,
    srdf: Option<PathBuf>,
    options: RobotImportOptions,
}

impl RobotDescription {
    /// The import options and files, paths resolved against `dir` with `vars`.
    fn resolve(&self, dir: &Path, vars: Variables<'_>) -> Result<Resolved, RobotError> {
        let mut packages = BTreeMap::new();
        for (name, path) in &self.packages {
            let field = format!("packages.{name}");
            packages.insert(name.clone(), resolve(&field, path, dir, vars)?);
        }
        let urdf = resolve_file("urdf", &self.urdf, dir, &packages, vars)?;
        let srdf = self
            .srdf
            .as_deref()
            .map(|s| resolve_file("srdf", s, dir, &packages, vars))
            .transpose()?;
        let options = RobotImportOptions {
            tool_link: self.tool.link.clone(),
            contact_links: self.tool.contact_links.clone(),
            package_paths: packages,
            base_dir: urdf.parent().map(Path::to_path_buf),
            arm_root: self.arm.root.clone(),
            tool_approach: self.tool.approach,
            frozen: self.frozen.clone(),
        };
        Ok(Resolved {
            urdf,
            srdf,
            options,
        })
    }
}

impl RobotModel {
    /// Loads the robot a description file describes (see
    /// [`RobotDescription`] for the format): paths relative to the file's directory,
    /// `${NAME}` from the process environment.
    ///
    /// # Errors
    /// As [`RobotModel::from_description`], and [`RobotError::Io`] if the file cannot be read.
    pub fn from_description_file(path: &Path) -> Result<RobotModel, RobotError> {
        let description = RobotDescription::from_file(path)?;
        let dir = path.parent().unwrap_or(Path::new(""));
        RobotModel::from_description(&description, dir, &|name| std::env::var(name).ok())
    }

    /// Loads the robot `description` describes, its relative paths against `dir`, its
    /// `${NAME}` variables looked up with `vars`. The steps: the URDF with the description's
    /// import options; the SRDF ([`RobotModel::with_srdf`]) or else sampled exemptions
    /// ([`RobotModel::with_sampled_pairs`], default sampling, without the pairs touching at
    /// the stow); then the stow (the SRDF's, the
    /// description's, or [`RobotModel::with_computed_stow`] with the default search); the base.
    ///
    /// # Errors
    /// [`RobotError::Description`] naming the field: an unknown base kind, a base limit or
    /// footprint radius that is not finite and positive, an unset variable, a `package://` name
    /// not in `[packages]`, a stow that misses an arm joint, names another joint, leaves the
    /// limits or is in self-collision; the URDF loader's errors
    /// ([`RobotModel::from_urdf_file_with`]) and the SRDF's ([`Srdf::from_file`],
    /// [`RobotModel::with_srdf`]); [`RobotError::NoStow`] when no stow is given and none is
    /// found.
    pub fn from_description(
        description: &RobotDescription,
        dir: &Path,
        vars: &dyn Fn(&str) -> Option<String>,
    ) -> Result<RobotModel, RobotError> {
        let kind = description.base.base_kind()?;
        check_base(&description.base)?;
        let resolved = description.resolve(dir, vars)?;
        let loaded = RobotModel::from_urdf_file_with(&resolved.urdf, &resolved.options)?;
        let stow = described_stow(&loaded, &description.stow)?;
        let srdf = resolved.srdf.as_deref().map(Srdf::from_file).transpose()?;
        let srdf_stow = srdf.as_ref().is_some_and(|s| loaded.srdf_stow(s).is_some());
        // The exemptions first: the computed stow is judged with them. Sampled ones leave out
        // the pairs touching at the stow, so a described stow in collision cannot exempt its
        // own collision (a computed stow touches only pairs the samples exempt anyway).
        let robot = match &srdf {
            Some(srdf) => loaded.with_srdf(srdf)?,
            None => {
                let pairs = loaded.sampled_pairs(&PairSampling::default(), false)?;
                loaded.with_allowed_pairs(pairs)?
            }
        };
        let robot = match &stow {
            Some(q) if !srdf_stow => robot.with_neutral(q)?,
            Some(_) => robot,
            None if srdf_stow => robot,
            None => robot.with_computed_stow(&StowSearch::default())?,
        };
        if let Some(q) = &stow {
            check_stow_free(&robot, q, "stow")?;
        }
        if let Some(state) = srdf.as_ref().and_then(|s| robot.srdf_stow(s)) {
            let field = format!("srdf group_state {:?}", state.name);
            check_stow_free(&robot, &robot.neutral(), &field)?;
        }
        let mut base = robot.base().clone();
        base.kind = kind;
        base.max_velocity = description.base.max_velocity;
        base.max_acceleration = description.base.max_acceleration;
        if let Some(radius) = described_radius(&description.base)? {
            base.footprint_radius = radius;
        }
        robot.with_base(base)
    }
}

/// The base's limits and footprint radius are finite and positive; a footprint polygon is a
/// polygon, and not given with a radius.
fn check_base(base: &BaseDescription) -> Result<(), RobotError> {
    let limits = [
        ("max_velocity", &base.max_velocity),
        ("max_acceleration", &base.max_acceleration),
    ];
    let differential = base.base_kind()? == BaseKind::DifferentialDrive;
    for (what, values) in limits {
        if differential && values[1] != 0.0 {
            return Err(RobotError::Description {
                field: format!("base.{what}[1]"),
                message: format!(
                    "a differential-drive base has no lateral motion: must be 0, got {}",
                    values[1]
                ),
            });
        }
        let lateral_free = |i: usize| differential && i == 1;
        if let Some(i) =
            (0..3).find(|&i| !(lateral_free(i) || values[i].is_finite() && values[i] > 0.0))
        {
            return Err(RobotError::Description {
                field: format!("base.{what}[{i}]"),
                message: format!("must be finite and > 0, got {}", values[i]),
            });
        }
    }
    match base.footprint_radius {
        Some(r) if !(r.is_finite() && r > 0.0) => Err(RobotError::Description {
            field: "base.footprint_radius".to_owned(),
            message: format!("must be finite and > 0, got {r}"),
        }),
        _ => described_radius(base).map(|_| ()),
    }
}

/// The footprint radius the description gives: `footprint_radius`, or the enclosing radius of
/// the `footprint` polygon; `None` when it gives neither.
fn described_radius(base: &BaseDescription) -> Result<Option<f64>, RobotError> {
    match (&base.footprint, base.footprint_radius) {
        (Some(_), Some(_)) => Err(RobotError::Description {
            field: "base.footprint".to_owned(),
            message: "give footprint or footprint_radius, not both".to_owned(),
        }),
        (Some(polygon), None) => super::footprint::polygon_radius(polygon).map(Some),
        (None, radius) => Ok(radius),
    }
}

/// The description's stow as an arm configuration (`None` when it gives none): every arm
/// joint named once, no other name, values within the limits.
fn described_stow(
    robot: &RobotModel,
    stow: &BTreeMap<String, f64>,
) -> Result<Option<DVector<f64>>, RobotError> {
    if stow.is_empty() {
        return Ok(None);
    }
    let invalid = |joint: &str, message: String| RobotError::Description {
        field: format!("stow.{joint}"),
        message,
    };
    if let Some(name) = stow
        .keys()
        .find(|name| !robot.arm_joints().iter().any(|j| &&j.name == name))
    {
        return Err(invalid(name, "not an arm joint".into()));
    }
    let mut q = DVector::zeros(robot.dof());
    for (value, joint) in q.iter_mut().zip(robot.arm_joints()) {
        let &v = stow.get(&joint.name).ok_or_else(|| {
            invalid(
                &joint.name,
                "missing: the stow names every arm joint".into(),
            )
        })?;
        if !(v.is_finite() && (joint.lower..=joint.upper).contains(&v)) {
            return Err(invalid(
                &joint.name,
                format!("{v} outside the limits [{}, {}]", joint.lower, joint.upper),
            ));
        }
        *value = v;
    }
    Ok(Some(q))
}

/// The described stow is free of self-collision under the robot's exemptions.
fn check_stow_free(robot: &RobotModel, q: &DVector<f64>, field: &str) -> Result<(), RobotError> {
    let poses = robot.link_poses(&RobotConfig {
        base: [0.0; 3],
        arm: q.clone(),
    })?;
    let collision = RobotCollision::new(robot)?;
    match collision.self_collision(&poses) {
        None => Ok(()),
        Some((a, b)) => {
            // Named by the URDF links whose shapes touch (a frozen joint's links are carried
            // by the link above it).
            let closest = collision.closest_colliders(&poses, a, b);
            let name = |l: usize, c: Option<usize>| {
                let link = &robot.links()[l];
                match c.and_then(|c| link.source(c)) {
                    Some(s) if s != link.name => format!("{s:?} (carried by {:?})", link.name),
                    _ => format!("{:?}", link.name),
                }
            };
            Err(RobotError::Description {
                field: field.to_owned(),
                message: format!(
                    "links {} and {} collide in the stowed configuration",
                    name(a, closest.map(|c| c.0)),
                    name(b, closest.map(|c| c.1))
                ),
            })
        }
    }
}
