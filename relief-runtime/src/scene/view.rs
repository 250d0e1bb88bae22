//! Named views: a camera, a relief depth and a sampling level policy under one name, for a
//! scene file's `view` key, `--view` and a scene argument's `@view=NAME`.
//!
//! `dissertation` is the view of the public Steep Parallax demo (McGuire & McGuire 2005)
//! that Burger 2018's Lion comes from: bump scale 0.05, the quad tilted 20° from facing the
//! eye, a 25° field of view, mip-mapped heights.

use relief_dsl::spec::Lod;

use super::Scene;

/// A named view.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum View {
    /// The Steep Parallax demo's view: depth scale 0.05, 20° from the normal, 25° vertical
    /// field of view, `lod=auto`.
    Dissertation,
}

impl View {
    /// Every named view.
    pub const ALL: [View; 1] = [View::Dissertation];

    /// The view's name, as scene files, `--view` and scene arguments spell it.
    pub fn name(self) -> &'static str {
        match self {
            View::Dissertation => "dissertation",
        }
    }

    /// The view named `name`; an error naming the views there are (and the nearest one).
    pub fn parse(name: &str) -> Result<View, String> {
        if let Some(v) = View::ALL.iter().find(|v| v.name() == name) {
            return Ok(*v);
        }
        let names: Vec<&str> = View::ALL.iter().map(|v| v.name()).collect();
        let near = relief_dsl::spec::suggest::nearest(name, names.iter().copied())
            .map(|n| format!("; did you mean `{n}`?"))
            .unwrap_or_default();
        Err(format!("`{name}` is not a named view (views: {}{near})", names.join(", ")))
    }

    /// The relief depth the view sets, in texture units.
    pub fn depth_scale(self) -> f32 {
        match self {
            View::Dissertation => 0.05,
        }
    }

    /// The camera's angle from the surface normal, degrees.
    pub fn angle_deg(self) -> f32 {
        match self {
            View::Dissertation => 20.0,
        }
    }

    /// The camera's vertical field of view, degrees.
    pub fn fov_deg(self) -> f32 {
        match self {
            View::Dissertation => 25.0,
        }
    }

    /// The sampling level policy of pipelines that name none.
    pub fn lod(self) -> Lod {
        match self {
            View::Dissertation => Lod::Auto,
        }
    }

    /// Sets the view on `s`: depth scale, the camera's angle and field of view, `lod`. The
    /// azimuth, distance and target stay the scene's.
    pub fn apply(self, s: &mut Scene) {
        s.depth_scale = self.depth_scale();
        s.camera.angle_deg = self.angle_deg();
        s.camera.fov_deg = self.fov_deg();
        s.lod = Some(self.lod());
    }
}

/// The named view a scene label carries (`scene:rocks@view=dissertation`), if any: what a
/// reader of results needs to know which `lod` the scene applied to the pipelines measured
/// on it.
pub(crate) fn of_label(label: &str) -> Option<View> {
    let (_, suffix) = label.rsplit_once('@')?;
    suffix.split(',').find_map(|p| p.trim().strip_prefix("view=")).and_then(|n| View::parse(n).ok())
}
