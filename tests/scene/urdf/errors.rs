//! Bad input: one test per error kind, each asserting the variant and that the message names
//! the offending element (document and tree errors here; meshes, files and export in
//! `io_errors.rs`).

use kinscene::scene::urdf::{ImportOptions, read_str};
use kinscene::scene::{ElementKind, Error};

use super::{TempDir, robot};

/// Imports `xml` (meshes relative to `dir`), expecting an error whose message contains every
/// string of `names`.
pub fn fails(xml: &str, dir: Option<&TempDir>, names: &[&str]) -> Error {
    let options = ImportOptions {
        base_dir: dir.map(|d| d.path().to_path_buf()),
        ..ImportOptions::default()
    };
    let e = read_str(xml, &options).expect_err("import should fail");
    let message = e.to_string();
    for name in names {
        assert!(message.contains(name), "{message:?} does not name {name:?}");
    }
    e
}

/// `b` → `door` by joint `hinge` of `kind` with the given extra joint XML.
fn hinge(kind: &str, extra: &str) -> String {
    robot(&format!(
        r#"<link name="b"/><link name="door"/>
        <joint name="hinge" type="{kind}"><parent link="b"/><child link="door"/>{extra}</joint>"#
    ))
}

const LIMIT: &str = r#"<limit lower="0" upper="1" effort="0" velocity="0"/>"#;

#[test]
fn malformed_xml_is_a_parse_error() {
    let e = fails("<robot name=\"r\"><link name=\"a\"></robot>", None, &[]);
    assert!(
        matches!(&e, Error::UrdfParse { message } if !message.is_empty()),
        "{e:?}"
    );
    // urdf-rs's own validation (a <limit> without velocity) is reported the same way.
    let e = fails(
        &hinge("revolute", r#"<limit lower="0" upper="1"/>"#),
        None,
        &["velocity"],
    );
    assert!(matches!(e, Error::UrdfParse { .. }), "{e:?}");
}

#[test]
fn deep_nesting_is_rejected_before_parsing() {
    let n = 100_000;
    let xml = robot(&format!(
        "<link name=\"a\">{}{}</link>",
        "<x>".repeat(n),
        "</x>".repeat(n)
    ));
    let e = fails(&xml, None, &["nested"]);
    assert!(matches!(e, Error::UrdfParse { .. }), "{e:?}");
}

#[test]
fn duplicate_names() {
    let e = fails(
        &robot(r#"<link name="a"/><link name="a"/>"#),
        None,
        &["\"a\""],
    );
    assert_eq!(e, Error::DuplicateLink { name: "a".into() });
    let xml = robot(
        r#"<link name="a"/><link name="b"/><link name="c"/>
        <joint name="j" type="fixed"><parent link="a"/><child link="b"/></joint>
        <joint name="j" type="fixed"><parent link="a"/><child link="c"/></joint>"#,
    );
    let e = fails(&xml, None, &["\"j\""]);
    assert_eq!(
        e,
        Error::DuplicateName {
            kind: ElementKind::Joint,
            name: "j".into()
        }
    );
}

#[test]
fn missing_link() {
    let xml = robot(
        r#"<link name="a"/><joint name="j" type="fixed"><parent link="a"/><child link="ghost"/></joint>"#,
    );
    let e = fails(&xml, None, &["\"j\"", "\"ghost\""]);
    assert!(
        matches!(&e, Error::MissingLink { joint, role, link }
        if joint == "j" && role == "child" && link == "ghost"),
        "{e:?}"
    );
}

#[test]
fn several_roots_and_no_root() {
    let e = fails(
        &robot(r#"<link name="a"/><link name="b"/>"#),
        None,
        &["\"a\"", "\"b\""],
    );
    assert_eq!(
        e,
        Error::SeveralRoots {
            links: vec!["a".into(), "b".into()]
        }
    );
    let e = fails(&robot(""), None, &["\"test\""]);
    assert_eq!(
        e,
        Error::NoRoot {
            robot: "test".into()
        }
    );
}

#[test]
fn link_with_two_parents() {
    let xml = robot(
        r#"<link name="a"/><link name="b"/><link name="c"/>
        <joint name="j1" type="fixed"><parent link="a"/><child link="c"/></joint>
        <joint name="j2" type="fixed"><parent link="b"/><child link="c"/></joint>"#,
    );
    let e = fails(&xml, None, &["\"c\"", "\"j1\"", "\"j2\""]);
    assert_eq!(
        e,
        Error::SeveralParents {
            link: "c".into(),
            joints: vec!["j1".into(), "j2".into()]
        }
    );
}

#[test]
fn cycles() {
    // A root plus a detached loop b → c → b.
    let xml = robot(
        r#"<link name="a"/><link name="b"/><link name="c"/>
        <joint name="j1" type="fixed"><parent link="b"/><child link="c"/></joint>
        <joint name="j2" type="fixed"><parent link="c"/><child link="b"/></joint>"#,
    );
    let e = fails(&xml, None, &["\"b\"", "\"c\""]);
    assert!(
        matches!(&e, Error::Cycle { parts } if parts.len() == 2),
        "{e:?}"
    );
    // Every link on a loop: no root at all; a self-loop is a cycle of one.
    let xml = robot(
        r#"<link name="a"/><joint name="j" type="fixed"><parent link="a"/><child link="a"/></joint>"#,
    );
    assert_eq!(
        fails(&xml, None, &["\"a\""]),
        Error::Cycle {
            parts: vec!["a".into()]
        }
    );
}

#[test]
fn unsupported_joint_types() {
    for kind in ["planar", "floating", "spherical"] {
        let e = fails(&hinge(kind, ""), None, &["\"hinge\"", kind]);
        assert_eq!(
            e,
            Error::UnsupportedJointType {
                joint: "hinge".into(),
                kind: kind.into()
            }
        );
    }
}

#[test]
fn missing_limits() {
    for kind in ["revolute", "prismatic"] {
        let e = fails(&hinge(kind, ""), None, &["\"hinge\""]);
        assert_eq!(
            e,
            Error::MissingLimits {
                joint: "hinge".into(),
                kind: kind.into()
            }
        );
    }
    // URDF 1.2: a <limit> without bounds means "no limit".
    let xml = hinge("revolute", r#"<limit effort="1" velocity="1"/>"#).replace(
        "<robot name=\"test\">",
        "<robot name=\"test\" version=\"1.2\">",
    );
    assert!(matches!(
        fails(&xml, None, &["\"hinge\""]),
        Error::MissingLimits { .. }
    ));
}

#[test]
fn lower_limit_above_upper() {
    let xml = hinge(
        "revolute",
        r#"<limit lower="1" upper="0" effort="0" velocity="0"/>"#,
    );
    let e = fails(&xml, None, &["\"hinge\""]);
    assert_eq!(
        e,
        Error::InvalidLimits {
            joint: "hinge".into(),
            lower: 1.0,
            upper: 0.0
        }
    );
}

#[test]
fn zero_and_nan_axes_name_the_joint() {
    let e = fails(
        &hinge("revolute", &format!(r#"<axis xyz="0 0 0"/>{LIMIT}"#)),
        None,
        &["\"hinge\""],
    );
    assert_eq!(
        e,
        Error::ZeroAxis {
            joint: "hinge".into()
        }
    );
    let e = fails(
        &hinge("prismatic", &format!(r#"<axis xyz="NaN 0 1"/>{LIMIT}"#)),
        None,
        &["\"hinge\""],
    );
    assert!(matches!(e, Error::NonFinite { .. }), "{e:?}");
}

#[test]
fn non_finite_numbers_name_the_element() {
    let xml = hinge("revolute", &format!(r#"<origin xyz="inf 0 0"/>{LIMIT}"#));
    assert!(matches!(
        fails(&xml, None, &["\"hinge\"", "origin"]),
        Error::NonFinite { .. }
    ));
    let xml = robot(
        r#"<link name="a"><collision><geometry><box size="1 0 1"/></geometry></collision></link>"#,
    );
    assert!(matches!(
        fails(&xml, None, &["\"a\"", "collision 0"]),
        Error::NonPositive { .. }
    ));
}

#[test]
fn handle_on_the_base() {
    let xml = robot(
        r#"<link name="a"/><link name="tap_handle"/>
        <joint name="j" type="fixed"><parent link="a"/><child link="tap_handle"/></joint>"#,
    );
    assert_eq!(
        fails(&xml, None, &["\"tap_handle\""]),
        Error::HandleOnBase {
            handle: "tap_handle".into()
        }
    );
}
