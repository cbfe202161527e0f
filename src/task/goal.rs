//! Goals: per-joint targets, the start state and the robot, as serde documents and as the
//! validated [`Problem`] the planner reads.
//!
//! # Goal file schema (TOML or JSON)
//! ```toml
//! [goal]                         # required: joint name -> target
//! dishwasher_door = { min = 1.4 }          # interval; a missing end is the joint's limit
//! drawer_3 = 0.15                          # exact value, tolerance DEFAULT_TOLERANCE
//! door_2 = { value = 1.2, tolerance = 0.05 }
//!
//! [start]                        # optional: joint name -> value (rad or m)
//! door_1 = 1.2                   # unnamed joints start at 0 clamped into their limits
//!
//! [robot]                        # optional
//! base = [2.0, -1.0, 0.0]        # x (m), y (m), yaw (rad); default: see RobotSpec
//! radius = 0.3                   # footprint radius (m), default DEFAULT_ROBOT_RADIUS
//! ```
//! Joints not named in `[goal]` are free: the planner may move them (to unblock a path or a
//! sweep) and leaves them wherever the plan ends.

use std::collections::BTreeMap;
use std::path::Path;

use serde::{Deserialize, Serialize};

use super::Error;
use crate::scene::{JointId, SceneModel, State};

/// Tolerance (rad or m) of an exact target written as a bare number: 1e-3.
pub const DEFAULT_TOLERANCE: f64 = 1e-3;

/// Footprint radius (m) of the robot base when the goal file gives none: 0.3 (a Stretch-class
/// mobile manipulator's circumscribed radius with a small margin).
pub const DEFAULT_ROBOT_RADIUS: f64 = 0.3;

/// One joint's target as written in a goal file.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum TargetSpec {
    /// An exact value with [`DEFAULT_TOLERANCE`].
    Value(f64),
    /// A table: `{ value, tolerance }` or `{ min, max }` (either end optional).
    Table(TargetTable),
}

/// The table form of a [`TargetSpec`].
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TargetTable {
    /// Exact value (rad or m); excludes `min`/`max`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub value: Option<f64>,
    /// Tolerance around `value`, `>= 0`; default [`DEFAULT_TOLERANCE`].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tolerance: Option<f64>,
    /// Lower end of the target interval; default the joint's lower limit.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub min: Option<f64>,
    /// Upper end of the target interval; default the joint's upper limit.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max: Option<f64>,
}

/// The robot as written in a goal file.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RobotSpec {
    /// Start pose of the base: x (m), y (m), yaw (rad). `None`: the free cell of the start
    /// state's inflated occupancy grid nearest to the grid's centre.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub base: Option<[f64; 3]>,
    /// Radius (m) of the disc that contains the base footprint, `> 0`.
    #[serde(default = "default_radius")]
    pub radius: f64,
}

fn default_radius() -> f64 {
    DEFAULT_ROBOT_RADIUS
}

impl Default for RobotSpec {
    fn default() -> Self {
        RobotSpec {
            base: None,
            radius: DEFAULT_ROBOT_RADIUS,
        }
    }
}

/// A goal document: targets, optional start values, optional robot.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GoalSpec {
    /// Joint name → target.
    pub goal: BTreeMap<String, TargetSpec>,
    /// Joint name → start value; other joints start at 0 clamped into their limits.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub start: BTreeMap<String, f64>,
    /// The robot.
    #[serde(default)]
    pub robot: RobotSpec,
}

impl GoalSpec {
    /// Parses a TOML goal document.
    ///
    /// # Errors
    /// [`Error::Parse`] with the parser's message (line and column).
    pub fn from_toml(text: &str) -> Result<Self, Error> {
        toml::from_str(text).map_err(|e| Error::Parse {
            what: "goal TOML".into(),
            message: e.to_string().trim().replace('\n', " "),
        })
    }

    /// Parses a JSON goal document (same schema).
    ///
    /// # Errors
    /// [`Error::Parse`] with the parser's message.
    pub fn from_json(text: &str) -> Result<Self, Error> {
        serde_json::from_str(text).map_err(|e| Error::Parse {
            what: "goal JSON".into(),
            message: e.to_string(),
        })
    }

    /// The document as TOML.
    pub fn to_toml(&self) -> String {
        toml::to_string(self).unwrap_or_default()
    }
}

/// A closed interval `[min, max]` of joint values (rad or m).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Interval {
    /// Lower end.
    pub min: f64,
    /// Upper end, `>= min`.
    pub max: f64,
}

impl Interval {
    /// Whether `min <= value <= max`.
    pub fn contains(&self, value: f64) -> bool {
        self.min <= value && value <= self.max
    }

    /// The point of the interval nearest to `value`.
    pub fn nearest(&self, value: f64) -> f64 {
        value.clamp(self.min, self.max)
    }

    /// Distance from `value` to the interval (0 inside).
    pub fn distance(&self, value: f64) -> f64 {
        (self.min - value).max(value - self.max).max(0.0)
    }
}

/// A validated goal: for some joints, the interval their final value must lie in.
#[derive(Debug, Clone, PartialEq)]
pub struct Goal {
    pub(crate) targets: Vec<(JointId, Interval)>,
}

impl Goal {
    /// No targets (every state is a goal state).
    pub fn empty() -> Self {
        Goal {
            targets: Vec::new(),
        }
    }

    /// Adds or replaces the target of `joint`: its final value must lie in `interval`, which
    /// is intersected with the joint's limits.
    ///
    /// # Errors
    /// [`Error::InvalidTarget`] for NaN or `min > max`; [`Error::TargetOutsideLimits`] if the
    /// interval misses the limits; a scene error for a foreign id.
    pub fn set(
        &mut self,
        model: &SceneModel,
        joint: JointId,
        interval: Interval,
    ) -> Result<&mut Self, Error> {
        let j = model.joint(joint).ok_or(crate::scene::Error::UnknownId {
            kind: crate::scene::ElementKind::Joint,
            index: joint.index(),
        })?;
        let bad = |message: String| Error::InvalidTarget {
            joint: j.name.clone(),
            message,
        };
        if interval.min.is_nan() || interval.max.is_nan() {
            return Err(bad("NaN bound".into()));
        }
        if interval.min > interval.max {
            return Err(bad(format!("min {} > max {}", interval.min, interval.max)));
        }
        let clipped = Interval {
            min: interval.min.max(j.limits.lower),
            max: interval.max.min(j.limits.upper),
        };
        if clipped.min > clipped.max {
            return Err(Error::TargetOutsideLimits {
                joint: j.name.clone(),
                min: interval.min,
                max: interval.max,
                lower: j.limits.lower,
                upper: j.limits.upper,
            });
        }
        self.targets.retain(|(k, _)| *k != joint);
        self.targets.push((joint, clipped));
        self.targets.sort_by_key(|(k, _)| *k);
        Ok(self)
    }

    /// The targets, by joint id.
    pub fn targets(&self) -> &[(JointId, Interval)] {
        &self.targets
    }

    /// The target interval of `joint`, if it has one.
    pub fn target(&self, joint: JointId) -> Option<Interval> {
        self.targets
            .iter()
            .find(|(k, _)| *k == joint)
            .map(|(_, i)| *i)
    }

    /// Whether `state` satisfies every target.
    pub fn is_satisfied(&self, state: &State) -> bool {
        self.targets
            .iter()
            .all(|(j, i)| state.value(*j).is_some_and(|v| i.contains(v)))
    }
}

/// The robot: start pose and footprint.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Robot {
    /// Start pose x (m), y (m), yaw (rad); `None` as in [`RobotSpec::base`].
    pub base: Option<[f64; 3]>,
    /// Footprint radius (m).
    pub radius: f64,
}

impl Robot {
    /// The start position (x, y) as a list of at most one point: what the navigation grid must
    /// cover ([`SceneModel::covering`](crate::scene::SceneModel::covering)).
    pub fn start_point(&self) -> Vec<nalgebra::Point2<f64>> {
        self.base
            .iter()
            .map(|b| nalgebra::Point2::new(b[0], b[1]))
            .collect()
    }

    /// Validates a [`RobotSpec`].
    ///
    /// # Errors
    /// [`Error::InvalidRobot`] for a non-finite pose or a radius that is not finite and `> 0`.
    pub fn new(spec: &RobotSpec) -> Result<Self, Error> {
        if !(spec.radius.is_finite() && spec.radius > 0.0) {
            return Err(Error::InvalidRobot {
                message: format!("radius {} must be finite and > 0", spec.radius),
            });
        }
        if let Some(b) = spec.base
            && b.iter().any(|v| !v.is_finite())
        {
            return Err(Error::InvalidRobot {
                message: format!("base pose {b:?} is not finite"),
            });
        }
        Ok(Robot {
            base: spec.base,
            radius: spec.radius,
        })
    }
}

/// A validated planning problem: start state, goal and robot for one scene model.
#[derive(Debug, Clone, PartialEq)]
pub struct Problem {
    /// The start state Θ0.
    pub start: State,
    /// The goal.
    pub goal: Goal,
    /// The robot.
    pub robot: Robot,
}

impl Problem {
    /// Reads the goal file at `path` (JSON if its name ends in `.json`, TOML otherwise; the
    /// [`GoalSpec`] gives the schema) and resolves it against `model`.
    ///
    /// # Errors
    /// [`Error::Io`] if the file cannot be read; otherwise [`Error::InFile`] naming the file,
    /// around the error of [`GoalSpec::from_toml`] / [`GoalSpec::from_json`] or
    /// [`Problem::from_spec`].
    pub fn from_goal_file(model: &SceneModel, path: impl AsRef<Path>) -> Result<Self, Error> {
        let path = path.as_ref();
        let text = read_text(path)?;
        let is_json = path
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("json"));
        let spec = if is_json {
            GoalSpec::from_json(&text)
        } else {
            GoalSpec::from_toml(&text)
        };
        spec.and_then(|spec| Problem::from_spec(model, &spec))
            .map_err(|e| in_file(path, e))
    }

    /// Resolves a goal document against `model`.
    ///
    /// # Errors
    /// Scene errors for unknown joint names and start values outside the limits or NaN;
    /// [`Error::InvalidTarget`], [`Error::TargetOutsideLimits`], [`Error::InvalidRobot`].
    pub fn from_spec(model: &SceneModel, spec: &GoalSpec) -> Result<Self, Error> {
        let mut start = model.zero_state();
        for (name, value) in &spec.start {
            start.set_by_name(model, name, *value)?;
        }
        let mut goal = Goal::empty();
        for (name, target) in &spec.goal {
            let id = model.joint_id(name)?;
            let limits = model.joints()[id.index()].limits;
            let bad = |message: &str| Error::InvalidTarget {
                joint: name.clone(),
                message: message.into(),
            };
            let interval = match *target {
                TargetSpec::Value(v) => exact(v, DEFAULT_TOLERANCE).ok_or_else(|| bad("NaN"))?,
                TargetSpec::Table(t) => match (t.value, t.min, t.max) {
                    (Some(_), Some(_), _) | (Some(_), _, Some(_)) => {
                        return Err(bad("give either value (and tolerance) or min/max"));
                    }
                    (Some(v), None, None) => {
                        let tol = t.tolerance.unwrap_or(DEFAULT_TOLERANCE);
                        if !(tol >= 0.0 && tol.is_finite()) {
                            return Err(bad("tolerance must be finite and >= 0"));
                        }
                        exact(v, tol).ok_or_else(|| bad("NaN value"))?
                    }
                    (None, min, max) => {
                        if t.tolerance.is_some() {
                            return Err(bad("tolerance needs a value"));
                        }
                        if min.is_none() && max.is_none() {
                            return Err(bad("empty target: give value, min or max"));
                        }
                        Interval {
                            min: min.unwrap_or(limits.lower),
                            max: max.unwrap_or(limits.upper),
                        }
                    }
                },
            };
            goal.set(model, id, interval)?;
        }
        Ok(Problem {
            start,
            goal,
            robot: Robot::new(&spec.robot)?,
        })
    }
}

fn exact(v: f64, tol: f64) -> Option<Interval> {
    (!v.is_nan()).then_some(Interval {
        min: v - tol,
        max: v + tol,
    })
}

/// The text of the file at `path`.
pub(crate) fn read_text(path: &Path) -> Result<String, Error> {
    std::fs::read_to_string(path).map_err(|e| Error::Io {
        path: path.to_path_buf(),
        message: e.to_string(),
    })
}

/// `e`, as an error of the file at `path`.
pub(crate) fn in_file(path: &Path, e: Error) -> Error {
    Error::InFile {
        path: path.to_path_buf(),
        source: Box::new(e),
    }
}
