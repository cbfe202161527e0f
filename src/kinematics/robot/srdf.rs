//! SRDF (the Semantic Robot Description Format of MoveIt): the planning groups, named
//! configurations and self-collision exemptions that go with a robot's URDF.
//!
//! Read: `<group>` (its `<chain base_link tip_link>`, `<link>`, `<joint>` and sub-`<group>`
//! members), `<group_state>` (named configurations such as home or stow, one value per
//! single-coordinate joint, several for a multi-coordinate one) and `<disable_collisions>`
//! (link pairs never checked against each other, with the setup tool's reason). Every other
//! element (`virtual_joint`, `end_effector`, `passive_joint`, `link_sphere_approximations`, …)
//! is skipped. [`Srdf::to_xml`] writes the same subset back, so pairs computed by
//! [`super::RobotModel::with_sampled_pairs`] can be saved and given to MoveIt or to this crate.

use std::path::Path;

use super::RobotError;
use crate::scene::urdf::escape_attribute;

/// An SRDF document (the subset this crate uses).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Srdf {
    /// The `<robot name>`.
    pub robot: String,
    /// The planning groups, in document order.
    pub groups: Vec<SrdfGroup>,
    /// The named configurations, in document order.
    pub group_states: Vec<GroupState>,
    /// The self-collision exemptions, in document order.
    pub disabled: Vec<DisabledPair>,
}

/// A `<group>`: a planning group's members.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct SrdfGroup {
    /// Its name.
    pub name: String,
    /// Its `<chain>`: (base link, tip link).
    pub chain: Option<(String, String)>,
    /// Its `<link>` members.
    pub links: Vec<String>,
    /// Its `<joint>` members.
    pub joints: Vec<String>,
    /// Its sub-`<group>` members.
    pub subgroups: Vec<String>,
}

/// A `<group_state>`: a named configuration of a group's joints.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct GroupState {
    /// Its name (e.g. `home`, `ready`, `stow`).
    pub name: String,
    /// The group it configures.
    pub group: String,
    /// Joint name and its value(s) (rad or m; several for multi-coordinate joints).
    pub joints: Vec<(String, Vec<f64>)>,
}

/// A `<disable_collisions>`: a link pair that is never checked for self-collision.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct DisabledPair {
    /// One link.
    pub link1: String,
    /// The other link.
    pub link2: String,
    /// Why (`Adjacent`, `Always`, `Never`, `Default`, `User`, … as setup tools write it).
    pub reason: String,
}

/// Names of group states taken as the stowed configuration, most preferred first.
pub(super) const STOW_STATE_NAMES: [&str; 7] = [
    "stow",
    "stowed",
    "tuck",
    "tucked",
    "transport",
    "home",
    "ready",
];

impl Srdf {
    /// Parses SRDF text.
    ///
    /// # Errors
    /// [`RobotError::Srdf`] naming the element at fault: not XML, a root other than `<robot>`, a
    /// missing attribute, a `group_state` joint value that is not a finite number.
    pub fn parse(text: &str) -> Result<Srdf, RobotError> {
        let doc = roxmltree::Document::parse(text).map_err(|e| srdf_error("document", e))?;
        let root = doc.root_element();
        if root.tag_name().name() != "robot" {
            return Err(srdf_error(
                "document",
                format!("root element is <{}>, not <robot>", root.tag_name().name()),
            ));
        }
        let mut srdf = Srdf {
            robot: root.attribute("name").unwrap_or_default().to_string(),
            ..Srdf::default()
        };
        for node in root.children().filter(|n| n.is_element()) {
            match node.tag_name().name() {
                "group" => srdf.groups.push(group(&node)?),
                "group_state" => srdf.group_states.push(group_state(&node)?),
                "disable_collisions" => srdf.disabled.push(DisabledPair {
                    link1: attribute(&node, "link1")?,
                    link2: attribute(&node, "link2")?,
                    reason: node.attribute("reason").unwrap_or_default().to_string(),
                }),
                _ => {}
            }
        }
        Ok(srdf)
    }

    /// Reads and parses an SRDF file.
    ///
    /// # Errors
    /// [`RobotError::Io`] if the file cannot be read, else as [`Srdf::parse`].
    pub fn from_file(path: &Path) -> Result<Srdf, RobotError> {
        let text = std::fs::read_to_string(path).map_err(|e| RobotError::Io {
            path: path.to_path_buf(),
            message: e.to_string(),
        })?;
        Srdf::parse(&text)
    }

    /// The named configuration taken as the stowed one: the first group state named (in this
    /// order, case-insensitively) `stow`, `stowed`, `tuck`, `tucked`, `transport`, `home` or
    /// `ready`.
    pub fn stow_state(&self) -> Option<&GroupState> {
        STOW_STATE_NAMES.iter().find_map(|name| {
            self.group_states
                .iter()
                .find(|s| s.name.eq_ignore_ascii_case(name))
        })
    }

    /// The group state taken as the stowed configuration of the arm whose joints are `joints`:
    /// among the group states named as [`Srdf::stow_state`] names them, then those whose name
    /// has one of those words as a part (`tuck_right_arm`, `arm_home`: parts split at `_`, `-`,
    /// `.` and spaces), in that order of preference, the first that sets every joint of
    /// `joints`, else the first that sets any (a two-armed robot's SRDF tucks each arm in its
    /// own state). With `joints` empty, the first of them.
    pub fn stow_state_for(&self, joints: &[&str]) -> Option<&GroupState> {
        let named = |word: &str, s: &GroupState| s.name.eq_ignore_ascii_case(word);
        let part = |word: &str, s: &GroupState| {
            s.name
                .split(['_', '-', '.', ' '])
                .any(|p| p.eq_ignore_ascii_case(word))
        };
        let candidates: Vec<&GroupState> = STOW_STATE_NAMES
            .iter()
            .flat_map(|w| self.group_states.iter().filter(move |s| named(w, s)))
            .chain(
                STOW_STATE_NAMES
                    .iter()
                    .flat_map(|w| self.group_states.iter().filter(move |s| part(w, s))),
            )
            .collect();
        if joints.is_empty() {
            return candidates.first().copied();
        }
        let sets = |s: &GroupState, j: &str| s.joints.iter().any(|(name, _)| name == j);
        candidates
            .iter()
            .find(|s| joints.iter().all(|j| sets(s, j)))
            .or_else(|| {
                candidates
                    .iter()
                    .find(|s| joints.iter().any(|j| sets(s, j)))
            })
            .copied()
    }

    /// The document as SRDF text (groups, group states and disabled pairs; loads back with
    /// [`Srdf::parse`] to an equal value).
    ///
    /// # Errors
    /// [`RobotError::Srdf`] for a name XML 1.0 cannot hold (a control character).
    pub fn to_xml(&self) -> Result<String, RobotError> {
        let e = |text: &str| {
            escape_attribute(text).map_err(|e| srdf_error(&format!("name {text:?}"), e))
        };
        let mut out = String::from("<?xml version=\"1.0\"?>\n");
        out += &format!("<robot name=\"{}\">\n", e(&self.robot)?);
        for g in &self.groups {
            out += &format!("  <group name=\"{}\">\n", e(&g.name)?);
            if let Some((base, tip)) = &g.chain {
                out += &format!(
                    "    <chain base_link=\"{}\" tip_link=\"{}\"/>\n",
                    e(base)?,
                    e(tip)?
                );
            }
            for (tag, names) in [
                ("link", &g.links),
                ("joint", &g.joints),
                ("group", &g.subgroups),
            ] {
                for name in names {
                    out += &format!("    <{tag} name=\"{}\"/>\n", e(name)?);
                }
            }
            out += "  </group>\n";
        }
        for s in &self.group_states {
            out += &format!(
                "  <group_state name=\"{}\" group=\"{}\">\n",
                e(&s.name)?,
                e(&s.group)?
            );
            for (joint, values) in &s.joints {
                // `{}` prints the shortest text that parses back to the same f64.
                let values: Vec<String> = values.iter().map(|v| format!("{v}")).collect();
                out += &format!(
                    "    <joint name=\"{}\" value=\"{}\"/>\n",
                    e(joint)?,
                    values.join(" ")
                );
            }
            out += "  </group_state>\n";
        }
        for p in &self.disabled {
            out += &format!(
                "  <disable_collisions link1=\"{}\" link2=\"{}\" reason=\"{}\"/>\n",
                e(&p.link1)?,
                e(&p.link2)?,
                e(&p.reason)?
            );
        }
        out += "</robot>\n";
        Ok(out)
    }
}

impl std::str::FromStr for Srdf {
    type Err = RobotError;

    fn from_str(text: &str) -> Result<Srdf, RobotError> {
        Srdf::parse(text)
    }
}

fn srdf_error(element: &str, message: impl ToString) -> RobotError {
    RobotError::Srdf {
        element: element.to_string(),
        message: message.to_string(),
    }
}

/// The attribute `name` of `node`, or an error naming the element (and its `name`, if any).
fn attribute(node: &roxmltree::Node<'_, '_>, name: &str) -> Result<String, RobotError> {
    node.attribute(name).map(str::to_string).ok_or_else(|| {
        let tag = node.tag_name().name();
        let element = match node.attribute("name") {
            Some(n) => format!("<{tag} name=\"{n}\">"),
            None => format!("<{tag}> at byte {}", node.range().start),
        };
        srdf_error(&element, format!("missing attribute {name:?}"))
    })
}

fn group(node: &roxmltree::Node<'_, '_>) -> Result<SrdfGroup, RobotError> {
    let mut g = SrdfGroup {
        name: attribute(node, "name")?,
        ..SrdfGroup::default()
    };
    for child in node.children().filter(|n| n.is_element()) {
        match child.tag_name().name() {
            "chain" => {
                g.chain = Some((
                    attribute(&child, "base_link")?,
                    attribute(&child, "tip_link")?,
                ));
            }
            "link" => g.links.push(attribute(&child, "name")?),
            "joint" => g.joints.push(attribute(&child, "name")?),
            "group" => g.subgroups.push(attribute(&child, "name")?),
            _ => {}
        }
    }
    Ok(g)
}

fn group_state(node: &roxmltree::Node<'_, '_>) -> Result<GroupState, RobotError> {
    let mut s = GroupState {
        name: attribute(node, "name")?,
        group: attribute(node, "group")?,
        joints: Vec::new(),
    };
    for child in node.children().filter(|n| n.is_element()) {
        if child.tag_name().name() != "joint" {
            continue;
        }
        let joint = attribute(&child, "name")?;
        let text = attribute(&child, "value")?;
        let values: Option<Vec<f64>> = text
            .split_whitespace()
            .map(|v| v.parse::<f64>().ok().filter(|v| v.is_finite()))
            .collect();
        match values {
            Some(values) if !values.is_empty() => s.joints.push((joint, values)),
            _ => {
                return Err(srdf_error(
                    &format!("<group_state name=\"{}\"> joint {joint:?}", s.name),
                    format!("value {text:?} is not a list of finite numbers"),
                ));
            }
        }
    }
    Ok(s)
}

#[cfg(test)]
mod tests {
    use super::*;

    const PANDA_LIKE: &str = r#"<?xml version="1.0"?>
<robot name="arm">
  <virtual_joint name="world" type="fixed" parent_frame="world" child_link="l0"/>
  <group name="arm"><chain base_link="l0" tip_link="l8"/></group>
  <group name="hand"><link name="hand"/><joint name="finger"/></group>
  <group_state name="ready" group="arm">
    <joint name="j1" value="0"/><joint name="j2" value="-0.785"/>
  </group_state>
  <group_state name="Stow" group="arm"><joint name="j1" value="1.5"/></group_state>
  <end_effector name="hand" parent_link="l8" group="hand"/>
  <disable_collisions link1="l0" link2="l1" reason="Adjacent"/>
  <disable_collisions link1="l5" link2="hand" reason="Never"/>
</robot>"#;

    #[test]
    fn reads_groups_states_and_pairs_and_writes_them_back() {
        let srdf = Srdf::parse(PANDA_LIKE).unwrap();
        assert_eq!(srdf.robot, "arm");
        assert_eq!(srdf.groups.len(), 2);
        assert_eq!(srdf.groups[0].chain, Some(("l0".into(), "l8".into())));
        assert_eq!(srdf.groups[1].joints, vec!["finger".to_string()]);
        assert_eq!(
            srdf.group_states[0].joints,
            vec![("j1".into(), vec![0.0]), ("j2".into(), vec![-0.785])]
        );
        assert_eq!(srdf.disabled.len(), 2);
        assert_eq!(srdf.disabled[1].reason, "Never");
        // "stow" ranks above "ready", matched without regard to case.
        assert_eq!(srdf.stow_state().unwrap().name, "Stow");
        assert_eq!(srdf.stow_state_for(&[]).unwrap().name, "Stow");
        assert_eq!(Srdf::parse(&srdf.to_xml().unwrap()).unwrap(), srdf);
        let bad = Srdf {
            robot: "bell\u{7}".into(),
            ..Srdf::default()
        };
        assert!(matches!(bad.to_xml(), Err(RobotError::Srdf { .. })));
    }

    /// A two-armed robot's SRDF tucks each arm in its own state (as PR2's does): the state
    /// for an arm is the one that sets its joints; a state named exactly comes first.
    #[test]
    fn each_arm_takes_the_stow_state_that_sets_its_joints() {
        let two_arms = r#"<robot name="two">
  <group_state name="tuck_left_arm" group="left_arm"><joint name="l1" value="0.5"/><joint name="l2" value="1"/></group_state>
  <group_state name="Tuck-Right-Arm" group="right_arm"><joint name="r1" value="-0.5"/><joint name="r2" value="1"/></group_state>
  <group_state name="wave" group="right_arm"><joint name="r1" value="2"/></group_state>
</robot>"#;
        let srdf = Srdf::parse(two_arms).unwrap();
        // Neither is named exactly as a stow.
        assert!(srdf.stow_state().is_none());
        assert_eq!(
            srdf.stow_state_for(&["r1", "r2"]).unwrap().name,
            "Tuck-Right-Arm"
        );
        assert_eq!(
            srdf.stow_state_for(&["l1", "l2"]).unwrap().name,
            "tuck_left_arm"
        );
        // One joint of the arm set: still that arm's.
        assert_eq!(
            srdf.stow_state_for(&["r2", "r3"]).unwrap().name,
            "Tuck-Right-Arm"
        );
        assert!(srdf.stow_state_for(&["x"]).is_none());
        // "tuck" must be a whole part of the name.
        let tucker = Srdf::parse(
            r#"<robot><group_state name="tucker" group="a"><joint name="r1" value="0"/></group_state></robot>"#,
        )
        .unwrap();
        assert!(tucker.stow_state_for(&["r1"]).is_none());
        // A state named exactly comes before a part match.
        let both = two_arms.replace("wave", "home");
        let both = Srdf::parse(&both).unwrap();
        assert_eq!(both.stow_state_for(&["r1"]).unwrap().name, "home");
    }

    #[test]
    fn bad_documents_name_the_element() {
        let missing = r#"<robot name="r"><disable_collisions link1="a"/></robot>"#;
        let e = Srdf::parse(missing).unwrap_err().to_string();
        assert!(
            e.contains("disable_collisions") && e.contains("link2"),
            "{e}"
        );
        let nan = r#"<robot><group_state name="s" group="g"><joint name="j" value="NaN"/></group_state></robot>"#;
        let e = Srdf::parse(nan).unwrap_err().to_string();
        assert!(e.contains("\"s\"") && e.contains("\"j\""), "{e}");
        assert!(Srdf::parse("<urdf/>").is_err());
        assert!(Srdf::parse("<robot").is_err());
    }
}
