//! Tests of the kitchen example's pictures.
//!
//! The pictures are checked as XML (a small well-formedness checker below: balanced tags,
//! quoted attributes, escaped text), by counting the elements each body and plan step must
//! produce, and by reading coordinates back: the world → pixel map documented on
//! `TopViewOptions` is recomputed here by hand for scenes whose geometry is known exactly.

use std::collections::BTreeMap;
use std::f64::consts::FRAC_PI_4;

use kinscene::motion::timing::{TimedPath, time_parameterise};
use kinscene::planner::{MotionPlan, StepMode, StepMotion, StepTiming};
use kinscene::scene::urdf::{self, ImportOptions};
use kinscene::scene::{
    BaseShape, Handle, Joint, Limits, PartSpec, SceneModel, SceneModelBuilder, Shape, State,
};
use kinscene::task::{Plan, Step};
use nalgebra::{Isometry2, Isometry3, Point3, Translation3, UnitQuaternion, Vector3};

use crate::report::svg::{
    self, Series, SvgError, TITLE_HEIGHT_PX, TopViewOptions, bar_chart, line_chart, stacked_bars,
    top_view, top_view_with,
};

// ---------------------------------------------------------------------------------------------
// A small XML well-formedness checker and element readers.

/// Checks `doc` is well-formed XML of the kind the pictures use: an optional `<?xml ?>`
/// prolog, one root element, balanced and properly nested tags, double-quoted attribute values
/// without `<`, unique attribute names, and `&` only in the five named or numeric entities.
/// Returns the number of elements.
fn check_xml(doc: &str) -> Result<usize, String> {
    let mut rest = doc.trim_start();
    if let Some(after) = rest.strip_prefix("<?xml") {
        let end = after.find("?>").ok_or("unterminated prolog")?;
        rest = &after[end + 2..];
    }
    let mut stack: Vec<String> = Vec::new();
    let mut elements = 0;
    let mut roots = 0;
    loop {
        let Some(lt) = rest.find('<') else {
            check_text(rest)?;
            if !rest.trim().is_empty() && stack.is_empty() {
                return Err("text after the root element".into());
            }
            break;
        };
        let text = &rest[..lt];
        check_text(text)?;
        if stack.is_empty() && !text.trim().is_empty() {
            return Err(format!("text outside the root: {text:?}"));
        }
        rest = &rest[lt..];
        if let Some(after) = rest.strip_prefix("<!--") {
            let end = after.find("-->").ok_or("unterminated comment")?;
            rest = &after[end + 3..];
            continue;
        }
        let gt = rest.find('>').ok_or("unterminated tag")?;
        let tag = &rest[1..gt];
        rest = &rest[gt + 1..];
        if let Some(name) = tag.strip_prefix('/') {
            let open = stack
                .pop()
                .ok_or(format!("closing </{name}> without opening"))?;
            if open != name.trim() {
                return Err(format!("<{open}> closed by </{name}>"));
            }
            continue;
        }
        let (body, self_closing) = match tag.strip_suffix('/') {
            Some(b) => (b, true),
            None => (tag, false),
        };
        let name_end = body.find(|c: char| c.is_whitespace()).unwrap_or(body.len());
        let name = &body[..name_end];
        if name.is_empty()
            || !name
                .chars()
                .all(|c| c.is_alphanumeric() || "-_:.".contains(c))
        {
            return Err(format!("bad element name {name:?}"));
        }
        check_attributes(&body[name_end..])?;
        if stack.is_empty() {
            roots += 1;
        }
        elements += 1;
        if !self_closing {
            stack.push(name.to_string());
        }
    }
    if let Some(open) = stack.pop() {
        return Err(format!("<{open}> never closed"));
    }
    if roots != 1 {
        return Err(format!("{roots} root elements"));
    }
    Ok(elements)
}

fn check_text(text: &str) -> Result<(), String> {
    if text.contains('>') {
        return Err(format!("unescaped '>' in text {text:?}"));
    }
    check_entities(text)
}

fn check_entities(text: &str) -> Result<(), String> {
    let mut rest = text;
    while let Some(amp) = rest.find('&') {
        let after = &rest[amp + 1..];
        let semi = after.find(';').ok_or(format!("bare '&' in {text:?}"))?;
        let entity = &after[..semi];
        let named = ["amp", "lt", "gt", "quot", "apos"].contains(&entity);
        let numeric = entity
            .strip_prefix('#')
            .is_some_and(|d| !d.is_empty() && d.chars().all(|c| c.is_ascii_digit()));
        if !named && !numeric {
            return Err(format!("unknown entity &{entity}; in {text:?}"));
        }
        rest = &after[semi + 1..];
    }
    Ok(())
}

fn check_attributes(mut s: &str) -> Result<(), String> {
    let mut names = Vec::new();
    loop {
        s = s.trim_start();
        if s.is_empty() {
            return Ok(());
        }
        let eq = s
            .find('=')
            .ok_or(format!("attribute without value: {s:?}"))?;
        let name = s[..eq].trim();
        if name.is_empty() || name.contains(char::is_whitespace) {
            return Err(format!("bad attribute name {name:?}"));
        }
        if names.contains(&name) {
            return Err(format!("duplicate attribute {name:?}"));
        }
        names.push(name);
        let value = s[eq + 1..]
            .strip_prefix('"')
            .ok_or(format!("unquoted attribute {name:?}"))?;
        let end = value
            .find('"')
            .ok_or(format!("unterminated attribute {name:?}"))?;
        let v = &value[..end];
        if v.contains('<') {
            return Err(format!("'<' in attribute {name:?}"));
        }
        check_entities(v)?;
        s = &value[end + 1..];
    }
}

/// The start tags of `element` whose `class` attribute is `class`, as attribute maps.
fn elements(doc: &str, element: &str, class: &str) -> Vec<BTreeMap<String, String>> {
    let open = format!("<{element} ");
    let mut out = Vec::new();
    let mut rest = doc;
    while let Some(i) = rest.find(&open) {
        let tag_start = &rest[i + open.len()..];
        let end = tag_start.find('>').expect("a start tag ends");
        let attrs = attributes(&tag_start[..end]);
        if attrs.get("class").map(String::as_str) == Some(class) {
            out.push(attrs);
        }
        rest = &tag_start[end..];
    }
    out
}

fn attributes(tag: &str) -> BTreeMap<String, String> {
    let mut map = BTreeMap::new();
    let mut s = tag;
    while let Some(eq) = s.find("=\"") {
        let name = s[..eq].trim().to_string();
        let value = &s[eq + 2..];
        let Some(end) = value.find('"') else { break };
        map.insert(name, value[..end].to_string());
        s = &value[end + 1..];
    }
    map
}

fn points(attr: &str) -> Vec<(f64, f64)> {
    attr.split_whitespace()
        .map(|p| {
            let (x, y) = p.split_once(',').expect("x,y pairs");
            (x.parse().expect("a number"), y.parse().expect("a number"))
        })
        .collect()
}

/// The subpaths of path data `M x,y x,y .. Z M ..` as point lists.
fn pieces(d: &str) -> Vec<Vec<(f64, f64)>> {
    d.split('M')
        .filter(|p| !p.trim().is_empty())
        .map(|p| points(p.trim().trim_end_matches('Z')))
        .collect()
}

fn num(attrs: &BTreeMap<String, String>, key: &str) -> f64 {
    attrs[key].parse().expect("a numeric attribute")
}

/// The `<g>` groups of `class` with their inner text (groups do not nest in the pictures).
fn groups<'a>(doc: &'a str, class: &str) -> Vec<(BTreeMap<String, String>, &'a str)> {
    let mut out = Vec::new();
    let mut rest = doc;
    while let Some(i) = rest.find("<g ") {
        let tag_start = &rest[i + 3..];
        let end = tag_start.find('>').expect("a start tag ends");
        let attrs = attributes(&tag_start[..end]);
        let inner = &tag_start[end + 1..];
        let close = inner.find("</g>").expect("a group closes");
        if attrs.get("class").map(String::as_str) == Some(class) {
            out.push((attrs, &inner[..close]));
        }
        rest = &tag_start[end..];
    }
    out
}

/// Every point of `got` is within `tol` of one of `want` and vice versa.
fn same_point_set(got: &[(f64, f64)], want: &[(f64, f64)], tol: f64) -> bool {
    let near =
        |a: &(f64, f64), b: &(f64, f64)| (a.0 - b.0).abs() <= tol && (a.1 - b.1).abs() <= tol;
    got.len() == want.len()
        && got.iter().all(|g| want.iter().any(|w| near(g, w)))
        && want.iter().all(|w| got.iter().any(|g| near(g, w)))
}

// ---------------------------------------------------------------------------------------------
// Scenes and plans.

fn kitchen() -> SceneModel {
    let path = crate::repository().join("examples/scenes/kitchen.urdf");
    urdf::read_file(path, &ImportOptions::default()).expect("examples/scenes/kitchen.urdf loads")
}

/// A 4 m × 2 m floor (x in [0, 4], y in [0, 2], top at z = 0), a counter box centred at
/// (1, 1.5) of 0.6 × 0.4 m, a box of 0.4 × 0.4 m at (3, 1) turned 45° about z, a cylinder of
/// radius 0.1 at (2, 0.5), and a drawer front (0.4 × 0.02 m in xy) centred at (1, 1.28)
/// sliding along −y from the counter's front, its handle at (1, 1.25).
fn known_scene() -> SceneModel {
    let mut b = SceneModelBuilder::new();
    b.add_base_shape(BaseShape::new(
        "floor",
        Shape::box_size(Vector3::new(4.0, 2.0, 0.1)),
        Isometry3::translation(2.0, 1.0, -0.05),
    ));
    b.add_base_shape(BaseShape::new(
        "counter",
        Shape::box_size(Vector3::new(0.6, 0.4, 0.9)),
        Isometry3::translation(1.0, 1.5, 0.45),
    ));
    b.add_base_shape(BaseShape::new(
        "turned",
        Shape::box_size(Vector3::new(0.4, 0.4, 1.0)),
        Isometry3::from_parts(
            Translation3::new(3.0, 1.0, 0.5),
            UnitQuaternion::from_axis_angle(&Vector3::z_axis(), FRAC_PI_4),
        ),
    ));
    b.add_base_shape(BaseShape::new(
        "post",
        Shape::cylinder(0.1, 0.8),
        Isometry3::translation(2.0, 0.5, 0.4),
    ));
    b.add_part(
        PartSpec::on_base(
            "drawer",
            Joint::prismatic(
                "drawer_slide",
                Point3::new(1.0, 1.28, 0.6),
                -Vector3::y(),
                Limits::new(0.0, 0.35),
            ),
        )
        .with_collider(
            Shape::box_size(Vector3::new(0.4, 0.02, 0.2)),
            Isometry3::identity(),
        )
        .with_handle(Handle::new(
            "drawer_handle",
            Point3::new(0.0, -0.03, 0.0),
            -Vector3::y(),
        )),
    );
    b.build().expect("the known scene is valid")
}

/// The pixel of world (x, y) in `known_scene`'s top view without a plan, by the documented
/// map: bounds are the floor's, x in [0, 4] and y in [0, 2]; with width 900, max height 1100
/// and margin 40, s = min((900 − 80) / 4, (1100 − 80) / 2) = min(205, 510) = 205 px/m; the
/// drawing is exactly as wide as the room, so left = 40 + (820 − 4·205) / 2 = 40, and
/// top = TITLE_HEIGHT_PX + 40.
fn known_px(x: f64, y: f64) -> (f64, f64) {
    let s = 205.0;
    (40.0 + x * s, TITLE_HEIGHT_PX + 40.0 + (2.0 - y) * s)
}

fn known_options() -> TopViewOptions {
    TopViewOptions {
        width_px: 900.0,
        max_height_px: 1100.0,
        margin_px: 40.0,
        ..TopViewOptions::default()
    }
}

/// A timed base path through `waypoints` ([x, y, yaw]).
fn base_path(waypoints: &[[f64; 3]]) -> TimedPath {
    let path: Vec<Vec<f64>> = waypoints.iter().map(|w| w.to_vec()).collect();
    time_parameterise(&path, &[0.5, 0.5, 1.0], &[0.5, 0.5, 1.0], Some(2)).expect("a valid path")
}

/// A motion step: the joint change with its base path and pose; the arm stays still (its
/// paths are single stowed configurations, which the top view does not draw).
fn step(joint: &str, from: f64, to: f64, path: &[[f64; 3]]) -> StepMotion {
    let still = time_parameterise(&[vec![0.0; 7]], &[1.0; 7], &[1.0; 7], None)
        .expect("a one-waypoint arm path");
    let base_path = base_path(path);
    StepMotion {
        joint: joint.into(),
        from,
        to,
        handle: format!("{joint}_handle"),
        base: *path.last().expect("a path has waypoints"),
        timing: StepTiming {
            base: base_path.duration,
            ..StepTiming::default()
        },
        base_path,
        approach: still.clone(),
        pregrasp: 0,
        manipulation: still.clone(),
        retreat: still,
        postgrasp: 0,
        manipulation_base: None,
        mode: StepMode::FixedBase,
        compared: None,
    }
}

fn motion_plan(steps: Vec<StepMotion>) -> MotionPlan {
    let task = Plan {
        steps: steps
            .iter()
            .map(|s| Step {
                joint: s.joint.clone(),
                from: s.from,
                to: s.to,
                handle: Some(s.handle.clone()),
                base: Some(s.base),
                travel: 0.0,
                cost: 0.0,
            })
            .collect(),
        cost: 0.0,
    };
    MotionPlan { task, steps }
}

// ---------------------------------------------------------------------------------------------
// Top view.

#[test]
fn kitchen_top_view_has_one_outline_per_shape_above_the_floor_and_per_part() {
    let model = kitchen();
    let doc = top_view(&model, &model.zero_state(), None, &[], "Kitchen").unwrap();
    check_xml(&doc).unwrap();

    // The kitchen's header: only the floor (top at z = 0) lies below 0.05 m; every other
    // base shape stands on it or hangs above it.
    let base = elements(&doc, "polygon", "base-shape");
    let names: Vec<&str> = base.iter().map(|a| a["data-name"].as_str()).collect();
    assert_eq!(base.len(), model.base().shapes.len() - 1, "{names:?}");
    assert!(!names.contains(&"floor"));
    for shape in model.base().shapes.iter().filter(|s| s.name != "floor") {
        assert!(
            names.contains(&shape.name.as_str()),
            "{} missing",
            shape.name
        );
    }
    // The three 2.4 m walls are walls; the wall cabinets (z from 1.4 m) overhead.
    let kind = |name: &str| {
        base.iter()
            .find(|a| a["data-name"] == name)
            .map(|a| a["data-kind"].clone())
            .unwrap()
    };
    for wall in ["wall_back", "wall_left", "wall_right"] {
        assert_eq!(kind(wall), "wall");
    }
    assert_eq!(kind("wall_cabinet_tall"), "overhead");
    assert_eq!(kind("island_worktop"), "counter");

    // One outline per part (all 11 kitchen parts have colliders), one dot per handle.
    let parts = elements(&doc, "path", "part");
    assert_eq!(parts.len(), model.parts().len());
    assert_eq!(parts.len(), 11);
    // Each part's outline has one closed piece per collider (overhead parts come last).
    for part in model.parts() {
        let attrs = parts
            .iter()
            .find(|a| a["data-name"] == part.name())
            .unwrap_or_else(|| panic!("{} drawn", part.name()));
        assert_eq!(
            pieces(&attrs["d"]).len(),
            part.colliders().len(),
            "{}",
            part.name()
        );
    }
    assert_eq!(
        elements(&doc, "circle", "handle").len(),
        model.handles().count()
    );
    // Every outline has at least 3 vertices (a box seen from above: 4).
    for p in &base {
        assert!(points(&p["points"]).len() >= 3, "{p:?}");
    }
    for p in &parts {
        assert!(
            pieces(&p["d"]).iter().all(|piece| piece.len() >= 3),
            "{p:?}"
        );
    }
    // No plan: no sweeps, paths or poses.
    assert!(groups(&doc, "sweep").is_empty());
    assert!(elements(&doc, "polyline", "base-path").is_empty());
}

#[test]
fn known_shapes_land_on_the_pixels_of_the_documented_map() {
    let model = known_scene();
    let doc = top_view_with(
        &model,
        &model.zero_state(),
        None,
        &[],
        "known",
        &known_options(),
    )
    .unwrap();
    check_xml(&doc).unwrap();
    // The default options are these ones: top_view draws the same picture.
    assert_eq!(
        top_view(&model, &model.zero_state(), None, &[], "known").unwrap(),
        doc
    );
    let base = elements(&doc, "polygon", "base-shape");
    let by_name = |name: &str| {
        points(
            &base
                .iter()
                .find(|a| a["data-name"] == name)
                .unwrap_or_else(|| panic!("{name} drawn"))["points"],
        )
    };
    // Pixels are printed with 2 decimals: 0.005 px rounding, 0.006 allowed.
    let tol = 0.006;
    // The counter: x in [0.7, 1.3], y in [1.3, 1.7].
    let counter: Vec<_> = [(0.7, 1.3), (1.3, 1.3), (1.3, 1.7), (0.7, 1.7)]
        .iter()
        .map(|&(x, y)| known_px(x, y))
        .collect();
    assert!(
        same_point_set(&by_name("counter"), &counter, tol),
        "{:?}",
        by_name("counter")
    );
    // (0.7, 1.3) by hand: (40 + 0.7·205, 76 + 0.7·205) = (183.5, 219.5) with a 36 px title.
    assert_eq!(TITLE_HEIGHT_PX, 36.0);
    assert!(same_point_set(
        &[known_px(0.7, 1.3)],
        &[(183.5, 219.5)],
        1e-9
    ));
    // The turned box: a diamond with vertices 0.2·√2 from (3, 1) along x and y.
    let d = 0.2 * 2f64.sqrt();
    let diamond: Vec<_> = [
        (3.0 + d, 1.0),
        (3.0, 1.0 + d),
        (3.0 - d, 1.0),
        (3.0, 1.0 - d),
    ]
    .iter()
    .map(|&(x, y)| known_px(x, y))
    .collect();
    assert!(
        same_point_set(&by_name("turned"), &diamond, tol),
        "{:?}",
        by_name("turned")
    );
    // The post: a 24-gon inscribed in its circle, 0.1·205 = 20.5 px around (2, 0.5).
    let post = by_name("post");
    let (cx, cy) = known_px(2.0, 0.5);
    assert_eq!(post.len(), 24);
    for (x, y) in &post {
        assert!(((x - cx).hypot(y - cy) - 20.5).abs() < 0.01, "({x}, {y})");
    }
    // The drawer front: x in [0.8, 1.2], y in [1.27, 1.29]; its handle at (1, 1.25).
    let drawer = elements(&doc, "path", "part");
    assert_eq!(drawer.len(), 1);
    let drawer = pieces(&drawer[0]["d"]);
    assert_eq!(drawer.len(), 1);
    let front: Vec<_> = [(0.8, 1.27), (1.2, 1.27), (1.2, 1.29), (0.8, 1.29)]
        .iter()
        .map(|&(x, y)| known_px(x, y))
        .collect();
    assert!(same_point_set(&drawer[0], &front, tol));
    let handle = &elements(&doc, "circle", "handle")[0];
    let (hx, hy) = known_px(1.0, 1.25);
    assert!((num(handle, "cx") - hx).abs() <= tol && (num(handle, "cy") - hy).abs() <= tol);
    // The floor is not drawn.
    assert!(base.iter().all(|a| a["data-name"] != "floor"));
}

#[test]
fn a_plan_draws_one_sweep_path_and_pose_per_step() {
    let model = known_scene();
    // Step 1 pulls the drawer 0 → 0.3 m from (1, 0.6) facing +y; step 2 pushes it back half
    // way. Both paths stay on the floor, so the map is the one of `known_px`.
    let plan = motion_plan(vec![
        step(
            "drawer_slide",
            0.0,
            0.3,
            &[[0.5, 0.4, 0.0], [1.0, 0.6, std::f64::consts::FRAC_PI_2]],
        ),
        step(
            "drawer_slide",
            0.3,
            0.15,
            &[
                [1.0, 0.6, std::f64::consts::FRAC_PI_2],
                [1.0, 0.55, std::f64::consts::FRAC_PI_2],
            ],
        ),
    ]);
    let trace = [
        Isometry2::new(nalgebra::Vector2::new(0.5, 0.4), 0.0),
        Isometry2::new(nalgebra::Vector2::new(1.0, 0.58), 1.5),
    ];
    let options = known_options();
    let doc = top_view_with(
        &model,
        &model.zero_state(),
        Some(&plan),
        &trace,
        "drawer & co <plan>",
        &options,
    )
    .unwrap();
    check_xml(&doc).unwrap();
    assert!(doc.contains("drawer &amp; co &lt;plan&gt;"));

    let sweeps = groups(&doc, "sweep");
    assert_eq!(sweeps.len(), 2);
    let tol = 0.006;
    for (k, (attrs, inner)) in sweeps.iter().enumerate() {
        assert_eq!(attrs["data-step"], (k + 1).to_string());
        let outlines = elements(inner, "path", "sweep-outline");
        // One moving part, sweep_samples values.
        assert_eq!(outlines.len(), options.sweep_samples);
        // Sample j is the drawer pulled out by from + j/7·(to − from) along −y.
        let (from, to) = [(0.0, 0.3), (0.3, 0.15)][k];
        for (j, o) in outlines.iter().enumerate() {
            let v = from + (to - from) * j as f64 / (options.sweep_samples - 1) as f64;
            let want: Vec<_> = [
                (0.8, 1.27 - v),
                (1.2, 1.27 - v),
                (1.2, 1.29 - v),
                (0.8, 1.29 - v),
            ]
            .iter()
            .map(|&(x, y)| known_px(x, y))
            .collect();
            assert!(
                same_point_set(&pieces(&o["d"]).concat(), &want, tol),
                "step {k} sample {j}"
            );
        }
    }
    // The legend lists the steps with their values.
    assert!(doc.contains("1. drawer_slide 0 \u{2192} 0.3"));
    assert!(doc.contains("2. drawer_slide 0.3 \u{2192} 0.15"));

    // Base paths through the waypoints, robot circles of 0.284·205 px at the base poses.
    let paths = elements(&doc, "polyline", "base-path");
    assert_eq!(paths.len(), 2);
    let want = [known_px(0.5, 0.4), known_px(1.0, 0.6)];
    assert!(same_point_set(&points(&paths[0]["points"]), &want, tol));
    let poses = groups(&doc, "robot-pose");
    assert_eq!(poses.len(), 2);
    let circle = &elements(poses[0].1, "circle", "footprint")[0];
    let (bx, by) = known_px(1.0, 0.6);
    assert!((num(circle, "cx") - bx).abs() <= tol && (num(circle, "cy") - by).abs() <= tol);
    assert!((num(circle, "r") - 0.284 * 205.0).abs() <= tol);
    // The heading tick of step 1 points to +y: up on the page by the radius.
    let tick = elements(poses[0].1, "line", "heading");
    assert_eq!(tick.len(), 1);
    assert!((num(&tick[0], "x2") - bx).abs() <= tol);
    assert!((num(&tick[0], "y2") - (by - 0.284 * 205.0)).abs() <= tol);
    // The executed trace as one dashed polyline.
    let traces = elements(&doc, "polyline", "trace");
    assert_eq!(traces.len(), 1);
    assert!(traces[0].contains_key("stroke-dasharray"));
    let want = [known_px(0.5, 0.4), known_px(1.0, 0.58)];
    assert!(same_point_set(&points(&traces[0]["points"]), &want, tol));
}

#[test]
fn a_nested_step_sweeps_the_part_and_its_descendants() {
    let model = kitchen();
    // The dishwasher door opens (the rack rides on it), then the rack slides out.
    let plan = motion_plan(vec![
        step(
            "dishwasher_door_hinge",
            0.0,
            1.5,
            &[[1.0, -0.5, 0.0], [2.5, 1.1, std::f64::consts::FRAC_PI_2]],
        ),
        step(
            "dishwasher_rack_slide",
            0.0,
            0.3,
            &[
                [2.5, 1.1, std::f64::consts::FRAC_PI_2],
                [2.4, 1.2, std::f64::consts::FRAC_PI_2],
            ],
        ),
    ]);
    let doc = top_view(&model, &model.zero_state(), Some(&plan), &[], "Dishwasher").unwrap();
    check_xml(&doc).unwrap();
    let sweeps = groups(&doc, "sweep");
    assert_eq!(sweeps.len(), 2);
    let samples = TopViewOptions::default().sweep_samples;
    // Step 1 moves the door and the rack on it; step 2 the rack only.
    assert_eq!(
        elements(sweeps[0].1, "path", "sweep-outline").len(),
        2 * samples
    );
    assert_eq!(
        elements(sweeps[1].1, "path", "sweep-outline").len(),
        samples
    );
    // The door opens towards the room (−y). Its lowest world y: closed, the handle bar's
    // outer face at 2.377 − 0.035 = 2.342 m (the bar stands 0.035 m proud of the slab's outer
    // face, y = 2.377); at 1.5 rad the slab's top outer edge at 2.377 − 0.74·sin 1.5 (the door
    // maps (y, z) to 2.377 + y·cos t − z·sin t; the bar, at z = 0.706 at most and y = −0.035,
    // stays above that). So the outline reaches 0.74·sin 1.5 − 0.035 m further towards −y.
    let outlines = elements(sweeps[0].1, "path", "sweep-outline");
    // Page y grows downwards: the lowest world y is the largest pixel y.
    let lowest_y_px = |o: &BTreeMap<String, String>| {
        pieces(&o["d"])
            .concat()
            .iter()
            .map(|p| p.1)
            .fold(f64::NEG_INFINITY, f64::max)
    };
    // Sample-major order: outline 0 is the door at 0, outline 2·(samples − 1) the door at 1.5
    // (the rack's outlines follow the door's at each sample).
    let closed = lowest_y_px(&outlines[0]);
    let open = lowest_y_px(&outlines[2 * (samples - 1)]);
    // The scale read off the same outline: the door is 0.594 m wide along x at every angle.
    let xs: Vec<f64> = pieces(&outlines[0]["d"])
        .concat()
        .iter()
        .map(|p| p.0)
        .collect();
    let width_px = xs.iter().copied().fold(f64::NEG_INFINITY, f64::max)
        - xs.iter().copied().fold(f64::INFINITY, f64::min);
    let scale = width_px / 0.594;
    let drop = 0.74 * 1.5f64.sin() - 0.035;
    // Pixels have 2 decimals (scale ≈ 230 px/m): 1e-4 m; 1 mm allowed.
    assert!(
        ((open - closed) / scale - drop).abs() < 1e-3,
        "door sweep {} m, expected {drop} m",
        (open - closed) / scale
    );
}

#[test]
fn bad_plans_and_traces_are_errors() {
    let model = known_scene();
    let start = model.zero_state();
    let unknown = motion_plan(vec![step("no_such_joint", 0.0, 0.1, &[[0.5, 0.4, 0.0]])]);
    assert!(matches!(
        top_view(&model, &start, Some(&unknown), &[], "x"),
        Err(SvgError::Step { step: 1, .. })
    ));
    let beyond = motion_plan(vec![step("drawer_slide", 0.0, 0.5, &[[0.5, 0.4, 0.0]])]);
    assert!(matches!(
        top_view(&model, &start, Some(&beyond), &[], "x"),
        Err(SvgError::Step { step: 1, .. })
    ));
    let mut nan_base = step("drawer_slide", 0.0, 0.1, &[[0.5, 0.4, 0.0]]);
    nan_base.base[2] = f64::NAN;
    assert!(matches!(
        top_view(&model, &start, Some(&motion_plan(vec![nan_base])), &[], "x"),
        Err(SvgError::NonFinite { .. })
    ));
    let trace = [Isometry2::new(nalgebra::Vector2::new(f64::NAN, 0.0), 0.0)];
    assert!(matches!(
        top_view(&model, &start, None, &trace, "x"),
        Err(SvgError::NonFinite { .. })
    ));
    let wrong_state = State::from_slice(&kitchen(), &[0.0; 11]).unwrap();
    assert!(matches!(
        top_view(&model, &wrong_state, None, &[], "x"),
        Err(SvgError::Scene(_))
    ));
    let bad = TopViewOptions {
        sweep_samples: 1,
        ..TopViewOptions::default()
    };
    assert!(matches!(
        top_view_with(&model, &start, None, &[], "x", &bad),
        Err(SvgError::OutOfRange { .. })
    ));
}

// ---------------------------------------------------------------------------------------------
// Charts.

fn cats(names: &[&str]) -> Vec<String> {
    names.iter().map(|s| s.to_string()).collect()
}

#[test]
fn bar_chart_heights_ticks_and_error_bars() {
    let categories = cats(&["seq A", "seq <B>"]);
    let series = vec![
        Series::new("Ours", vec![80.0, 60.0]),
        Series::new("Random & co", vec![20.0, 40.0]),
    ];
    let errors = vec![
        Series::new("Ours", vec![5.0, 10.0]),
        Series::new("Random & co", vec![0.0, 2.0]),
    ];
    let doc = bar_chart(
        "Success",
        &categories,
        &series,
        "success (%)",
        Some(100.0),
        Some(errors.as_slice()),
    )
    .unwrap();
    check_xml(&doc).unwrap();
    assert!(doc.contains("seq &lt;B&gt;") && doc.contains("Random &amp; co"));
    let bars = elements(&doc, "rect", "bar");
    assert_eq!(bars.len(), 4);
    // Heights proportional to the values on a 0..100 axis, sharing one baseline.
    let h: Vec<f64> = bars.iter().map(|b| num(b, "height")).collect();
    let bottoms: Vec<f64> = bars
        .iter()
        .map(|b| num(b, "y") + num(b, "height"))
        .collect();
    let unit = h[0] / 80.0;
    for (got, v) in h.iter().zip([80.0, 60.0, 20.0, 40.0]) {
        assert!((got - v * unit).abs() < 0.02, "{h:?}");
    }
    assert!(bottoms.iter().all(|b| (b - bottoms[0]).abs() < 0.02));
    // The plot is 320 px tall: 100 % is 320 px.
    assert!((unit * 100.0 - 320.0).abs() < 0.05);
    // Ticks: a step of 20 (100 / 5) from 0 to 100.
    let ticks: Vec<String> = tick_labels(&doc);
    assert_eq!(ticks, ["0", "20", "40", "60", "80", "100"]);
    // Error bars: three lines (stem and two caps) for every non-zero error: 3 of 4.
    assert_eq!(elements(&doc, "line", "error-bar").len(), 9);
}

fn tick_labels(doc: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut rest = doc;
    while let Some(i) = rest.find("<text ") {
        let after = &rest[i + 6..];
        let open = after.find('>').expect("a start tag ends");
        let close = after.find("</text>").expect("a text element closes");
        if attributes(&after[..open]).get("class").map(String::as_str) == Some("tick") {
            out.push(after[open + 1..close].to_string());
        }
        rest = &after[close..];
    }
    out
}

#[test]
fn nice_axes_round_out_to_whole_steps() {
    // 73 / 5 = 14.6 rounds up to a step of 20: 0, 20, .., 80.
    let a = svg::NiceAxis::new(0.0, 73.0, None);
    assert_eq!((a.lo, a.hi, a.step), (0.0, 80.0, 20.0));
    assert_eq!(a.ticks, [0.0, 20.0, 40.0, 60.0, 80.0]);
    // 1.1 / 5 = 0.22 → 0.25 (the 2.5 step), printed with 2 decimals.
    let a = svg::NiceAxis::new(0.0, 1.1, None);
    assert_eq!(a.step, 0.25);
    assert_eq!(a.hi, 1.25);
    assert_eq!(a.decimals, 2);
    assert_eq!(a.label(0.5), "0.50");
    // A negative minimum: −3..7 spans 10, step 2, from −4 to 8.
    let a = svg::NiceAxis::new(-3.0, 7.0, None);
    assert_eq!((a.lo, a.hi, a.step), (-4.0, 8.0, 2.0));
    assert_eq!(a.label(0.0), "0");
    // All zero: 0..1.
    let a = svg::NiceAxis::new(0.0, 0.0, None);
    assert_eq!((a.lo, a.hi), (0.0, 1.0));
}

#[test]
fn stacked_bars_stack_to_the_totals() {
    let categories = cats(&["Ours", "Random"]);
    let layers = vec![
        Series::new("success", vec![0.7, 0.25]),
        Series::new("part collision", vec![0.1, 0.45]),
        Series::new("path blocking", vec![0.2, 0.2]),
        Series::new("other", vec![0.0, 0.1]),
    ];
    let doc = stacked_bars("Outcomes", &categories, &layers, "share of runs").unwrap();
    check_xml(&doc).unwrap();
    let segments = elements(&doc, "rect", "segment");
    // Zero-height segments are left out: 4 + 3.
    assert_eq!(segments.len(), 7);
    // Each bar's segments touch and sum to its total (1.0 in both: the axis top 1 = 320 px).
    let stacks = groups(&doc, "stack");
    assert_eq!(stacks.len(), 2);
    for (_, inner) in &stacks {
        let mut segs: Vec<(f64, f64)> = elements(inner, "rect", "segment")
            .iter()
            .map(|s| (num(s, "y"), num(s, "height")))
            .collect();
        segs.sort_by(|a, b| a.0.total_cmp(&b.0));
        for w in segs.windows(2) {
            assert!((w[0].0 + w[0].1 - w[1].0).abs() < 0.02, "{segs:?}");
        }
        let total: f64 = segs.iter().map(|s| s.1).sum();
        assert!((total - 320.0).abs() < 0.05, "{total}");
    }
    // The first layer is at the bottom: "success" of Ours is 0.7·320 = 224 px tall.
    let success = elements(stacks[0].1, "rect", "segment")
        .into_iter()
        .find(|s| s["data-layer"] == "success")
        .unwrap();
    assert!((num(&success, "height") - 224.0).abs() < 0.02);
    assert!(doc.contains("part collision"));
}

#[test]
fn line_chart_maps_points_on_both_axes() {
    let x = [0.0, 0.005, 0.01, 0.02];
    let series = vec![
        Series::new("two-view", vec![0.5, 1.0, 2.0, 4.0]),
        Series::new("proprioceptive", vec![0.2, 0.4, 0.8, 1.6]),
    ];
    let doc = line_chart("Noise", "σ (m)", &x, &series, "angle error (°)", None).unwrap();
    check_xml(&doc).unwrap();
    let pts = elements(&doc, "circle", "point");
    assert_eq!(pts.len(), 8);
    // x axis 0..0.02 (step 0.005): x pixels equally spaced for 0, 0.005, 0.01, then doubled.
    let xs: Vec<f64> = pts[..4].iter().map(|p| num(p, "cx")).collect();
    let dx = xs[1] - xs[0];
    assert!((xs[2] - xs[1] - dx).abs() < 0.02 && (xs[3] - xs[2] - 2.0 * dx).abs() < 0.02);
    // y axis 0..4 (step 1): 4.0 sits at the top of the 320 px plot, 2.0 half way.
    let ys: Vec<f64> = pts[..4].iter().map(|p| num(p, "cy")).collect();
    assert!((ys[2] - ys[3] - 160.0).abs() < 0.02, "{ys:?}");
    assert_eq!(elements(&doc, "polyline", "line").len(), 2);
}

#[test]
fn charts_reject_nan_and_mismatched_lengths() {
    let categories = cats(&["a", "b"]);
    let nan = vec![Series::new("s", vec![1.0, f64::NAN])];
    let ok = vec![Series::new("s", vec![1.0, 2.0])];
    let short = vec![Series::new("s", vec![1.0])];
    assert!(matches!(
        bar_chart("t", &categories, &nan, "y", None, None),
        Err(SvgError::NonFinite { .. })
    ));
    assert!(matches!(
        bar_chart("t", &categories, &short, "y", None, None),
        Err(SvgError::DimensionMismatch {
            expected: 2,
            got: 1,
            ..
        })
    ));
    assert!(matches!(
        bar_chart("t", &categories, &ok, "y", Some(f64::NAN), None),
        Err(SvgError::NonFinite { .. })
    ));
    assert!(matches!(
        bar_chart("t", &categories, &ok, "y", None, Some(short.as_slice())),
        Err(SvgError::DimensionMismatch { .. })
    ));
    assert!(matches!(
        bar_chart("t", &categories, &ok, "y", None, Some(&[][..])),
        Err(SvgError::DimensionMismatch { .. })
    ));
    assert!(matches!(
        bar_chart("t", &[], &ok, "y", None, None),
        Err(SvgError::Empty { .. })
    ));
    assert!(matches!(
        stacked_bars("t", &categories, &nan, "y"),
        Err(SvgError::NonFinite { .. })
    ));
    assert!(matches!(
        stacked_bars("t", &categories, &short, "y"),
        Err(SvgError::DimensionMismatch { .. })
    ));
    assert!(matches!(
        stacked_bars("t", &categories, &[Series::new("s", vec![1.0, -1.0])], "y"),
        Err(SvgError::OutOfRange { .. })
    ));
    assert!(matches!(
        line_chart("t", "x", &[0.0, 1.0], &nan, "y", None),
        Err(SvgError::NonFinite { .. })
    ));
    assert!(matches!(
        line_chart("t", "x", &[0.0, f64::INFINITY], &ok, "y", None),
        Err(SvgError::NonFinite { .. })
    ));
    assert!(matches!(
        line_chart("t", "x", &[0.0, 1.0, 2.0], &ok, "y", None),
        Err(SvgError::DimensionMismatch { .. })
    ));
}

#[test]
fn the_xml_checker_rejects_broken_documents() {
    // The checker itself must be able to fail.
    assert!(check_xml("<svg><g></svg>").is_err());
    assert!(check_xml("<svg><g/></svg><svg/>").is_err());
    assert!(check_xml(r#"<svg a="1 & 2"/>"#).is_err());
    assert!(check_xml("<svg>a < b</svg>").is_err());
    assert!(check_xml("<svg>a > b</svg>").is_err());
    assert!(check_xml(r#"<svg a=1/>"#).is_err());
    assert_eq!(
        check_xml(r#"<?xml version="1.0"?><svg><g a="&amp;"/></svg>"#),
        Ok(2)
    );
}

#[test]
fn extreme_values_neither_hang_nor_panic() {
    // Finite but huge values: the axis step stays finite and the ticks bounded.
    let categories = cats(&["a", "b"]);
    let huge = vec![Series::new("s", vec![-1e308, 1e308])];
    let doc = bar_chart("t", &categories, &huge, "y", None, None).unwrap();
    check_xml(&doc).unwrap();
    assert!(tick_labels(&doc).len() <= 50);
    // A trace from x = −1e308 to 1e308 m: the drawing's extent overflows.
    let model = known_scene();
    let far = [
        Isometry2::new(nalgebra::Vector2::new(-1e308, 0.0), 0.0),
        Isometry2::new(nalgebra::Vector2::new(1e308, 0.0), 0.0),
    ];
    assert!(matches!(
        top_view(&model, &model.zero_state(), None, &far, "far"),
        Err(SvgError::OutOfRange { .. })
    ));
    // A far but representable trace still draws (the scene shrinks to a dot).
    let far = [Isometry2::new(nalgebra::Vector2::new(1e12, -1e12), 0.0)];
    check_xml(&top_view(&model, &model.zero_state(), None, &far, "far").unwrap()).unwrap();
}
