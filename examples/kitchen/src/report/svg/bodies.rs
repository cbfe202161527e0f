//! The scene in a top view: base-map shapes (walls, counters, overhead shapes), parts and
//! handles.

use kinscene::scene::{self, SceneData, SceneModel};
use nalgebra::Point2;

use super::SvgError;
use super::document::{Svg, escape, part_colour, px};
use super::geometry::{Bounds, Footprint, Outline, part_outline, shape_points};
use super::top_view::TopViewOptions;
use super::view::View;

/// The role of a drawn body, which sets its style.
#[derive(Clone, Copy, PartialEq)]
enum Kind {
    Wall,
    Counter,
    Overhead,
}

impl Kind {
    fn name(self) -> &'static str {
        match self {
            Kind::Wall => "wall",
            Kind::Counter => "counter",
            Kind::Overhead => "overhead",
        }
    }
}

/// The bodies of a scene at one state, ready to draw.
pub(super) struct Bodies {
    /// Base shapes reaching above the floor: name, role and outline, lowest top first.
    base_shapes: Vec<(String, Kind, Footprint)>,
    /// Parts with colliders: index and outline.
    parts: Vec<(usize, Outline)>,
    /// Handles: name and world xy (m).
    handles: Vec<(String, Point2<f64>)>,
}

impl Bodies {
    /// The base shapes, parts and handles of `model` at the poses in `data`. Every base shape
    /// (the floor included) and every part outline is added to `bounds`.
    ///
    /// # Errors
    /// [`SvgError::Scene`] when a handle's pose cannot be computed.
    pub(super) fn collect(
        model: &SceneModel,
        data: &SceneData,
        options: &TopViewOptions,
        bounds: &mut Bounds,
    ) -> Result<Bodies, SvgError> {
        let mut base_shapes: Vec<(String, Kind, Footprint)> = Vec::new();
        for shape in &model.base().shapes {
            let mut points = Vec::new();
            shape_points(&shape.shape, &shape.world_from_shape, &mut points);
            let Some(fp) = Footprint::of(&points) else {
                continue;
            };
            for p in &fp.outline {
                bounds.add(*p, 0.0);
            }
            if fp.z_max < options.floor_top {
                continue;
            }
            let kind = if fp.z_min >= options.overhead_bottom {
                Kind::Overhead
            } else if fp.z_min < options.floor_top && fp.z_max >= options.wall_height {
                Kind::Wall
            } else {
                Kind::Counter
            };
            base_shapes.push((shape.name.clone(), kind, fp));
        }
        base_shapes.sort_by(|a, b| a.2.z_max.total_cmp(&b.2.z_max));

        // The parts and handles at the start state.
        let mut parts: Vec<(usize, Outline)> = Vec::new();
        for index in 0..model.parts().len() {
            if let Some(fp) = part_outline(model, data, index) {
                for p in fp.points() {
                    bounds.add(*p, 0.0);
                }
                parts.push((index, fp));
            }
        }
        let mut handles: Vec<(String, Point2<f64>)> = Vec::new();
        for (id, handle) in model.handles() {
            let pose = scene::world_from_handle(model, data, id)?;
            handles.push((
                handle.name.clone(),
                Point2::new(pose.position.x, pose.position.y),
            ));
        }
        Ok(Bodies {
            base_shapes,
            parts,
            handles,
        })
    }

    /// Floor-level base shapes, floor-level parts, then overhead ones (dashed), then the
    /// handles, in a `<g class="scene">`.
    pub(super) fn draw(
        &self,
        svg: &mut Svg,
        view: &View,
        model: &SceneModel,
        options: &TopViewOptions,
    ) {
        let draw_base = |svg: &mut Svg, name: &str, kind: Kind, fp: &Footprint| {
            let style = match kind {
                Kind::Wall => r##"fill="#3a3a3a" stroke="#1e1e1e" stroke-width="1""##,
                Kind::Counter => r##"fill="#c4c4c4" stroke="#7a7a7a" stroke-width="0.8""##,
                Kind::Overhead => {
                    r##"fill="#9a9a9a" fill-opacity="0.08" stroke="#6a6a6a" stroke-width="0.8" stroke-dasharray="6 4""##
                }
            };
            svg.raw(&format!(
                r#"<polygon class="base-shape" data-kind="{}" data-name="{}" points="{}" {style}><title>{}</title></polygon>"#,
                kind.name(),
                escape(name),
                view.points(&fp.outline),
                escape(name),
            ));
        };
        let draw_part = |svg: &mut Svg, index: usize, fp: &Outline, overhead: bool| {
            let name = model.parts().get(index).map_or("", |p| p.name());
            let colour = part_colour(index);
            let style = if overhead {
                format!(
                    r##"fill="{colour}" fill-opacity="0.2" stroke="#555555" stroke-width="0.8" stroke-dasharray="4 3""##
                )
            } else {
                format!(
                    r##"fill="{colour}" fill-opacity="0.85" stroke="#444444" stroke-width="0.8""##
                )
            };
            svg.raw(&format!(
                r#"<path class="part" data-name="{}" d="{}" {style}><title>{}</title></path>"#,
                escape(name),
                view.path(fp),
                escape(name),
            ));
        };
        svg.raw(r#"<g class="scene">"#);
        for (name, kind, fp) in self.base_shapes.iter().filter(|b| b.1 != Kind::Overhead) {
            draw_base(svg, name, *kind, fp);
        }
        let overhead_part = |fp: &Outline| fp.z_min() >= options.overhead_bottom;
        for (index, fp) in self.parts.iter().filter(|p| !overhead_part(&p.1)) {
            draw_part(svg, *index, fp, false);
        }
        for (name, kind, fp) in self.base_shapes.iter().filter(|b| b.1 == Kind::Overhead) {
            draw_base(svg, name, *kind, fp);
        }
        for (index, fp) in self.parts.iter().filter(|p| overhead_part(&p.1)) {
            draw_part(svg, *index, fp, true);
        }
        for (name, p) in &self.handles {
            let (x, y) = view.px(*p);
            svg.raw(&format!(
                r##"<circle class="handle" data-name="{}" cx="{}" cy="{}" r="3" fill="#1a1a1a"><title>{}</title></circle>"##,
                escape(name),
                px(x),
                px(y),
                escape(name),
            ));
        }
        svg.raw("</g>");
    }
}
