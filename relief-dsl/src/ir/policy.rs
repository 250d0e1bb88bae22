//! What the composer decides for the code the builder writes, and a stage never sees: whether
//! loop passes and fetches are counted (the probe's copy), the mip level samples are taken at,
//! which texture a stage's read of a map becomes (a room's wall has its own), and where the
//! edge mode comes from (a library fixes it as a constant).
//!
//! The builder asks its function's [`Policy`] each time; the composer hands one to
//! [`ModuleCtx::function`](super::ModuleCtx::function) (and may swap it for a region with
//! [`FnBuilder::with_policy`](super::FnBuilder::with_policy)). [`Plain`] is relief's own render
//! code; the composer's other policies wrap or replace it.

use naga::Handle;

use crate::spec::Lod;

/// The composer's decisions for a function being built. Every method has the plain answer as
/// its default.
pub(crate) trait Policy {
    /// The private counter a loop pass adds one to, `None` when nothing is counted. A policy
    /// that counts passes counts texture fetches too (in [`super::counter::FETCHES`]).
    fn step_counter(&self) -> Option<&'static str> {
        None
    }
    /// The pipeline's `lod`: under anything but [`Lod::Zero`] every 2D sample is taken at the
    /// level in the private `relief_sample_level`, which the entry points set.
    fn lod(&self) -> Lod {
        Lod::Zero
    }
    /// The module constant (a `bool`) stages read the edge mode from, instead of the `Params`
    /// block; `None`: the `Params` block.
    fn edge_clamp_constant(&self) -> Option<Handle<naga::Constant>> {
        None
    }
    /// Where the texture a stage reads as `name` at `binding` (relief's own binding numbers,
    /// [`crate::abi::binding`]) is declared.
    fn texture(&self, name: &str, binding: u32) -> TextureSite {
        TextureSite { name: name.to_string(), binding, wall: None }
    }
    /// Whether every height read adds the quadric of the curved base surface (a mesh module
    /// under `curved=quadric`, Oliveira & Policarpo 2005): see
    /// [`crate::stage::sampling::QUADRIC_COEFFS`].
    fn quadric_warp(&self) -> bool {
        false
    }
    /// Whether every height read adds the prism's lift (a mesh module or library under
    /// `curved=prism`, so that the search runs from the prism fragment's entry): see
    /// [`crate::stage::sampling::PRISM_LIFT`].
    fn prism_lift(&self) -> bool {
        false
    }
    /// Whether, under the prism's lift, the coarse stage reads a precomputed map (cone
    /// ratios, a cell's apex, max-mip levels, the distance field): the bent chord is then
    /// searched as straight pieces, each untilted where it descends (`compose::mesh`'s
    /// `piece_search`), so that the lift is a constant there and the maps' bounds, made for
    /// the unlifted field, still hold once their absolute heights carry the same constant
    /// ([`crate::ir::FnBuilder::map_height`]).
    fn prism_untilted(&self) -> bool {
        false
    }
    /// Whether the linear searches scale their layer count by the private
    /// [`crate::stage::sampling::LAYER_SHARE`] (the prism walk's chords, each given its share
    /// of the relief's layers).
    fn layer_share(&self) -> bool {
        false
    }
    /// Whether the safe marches whose cell map carries its apex read their cells' patches
    /// from the patch map (`MapReq::patches_read_with`); `false`: they gather the corners, the
    /// form before the patch map (`compose::Options::cell_patch_gather`, for the check that
    /// both give the same hits).
    fn cell_patches(&self) -> bool {
        true
    }
}

/// Where a policy declares a texture: its name and binding in the module, and the room wall
/// whose image it is (`None`: the module's only copy).
#[derive(Clone, Debug, PartialEq, Eq)]
pub(crate) struct TextureSite {
    /// The global's name.
    pub(crate) name: String,
    /// Its binding (group 0).
    pub(crate) binding: u32,
    /// The room wall it belongs to.
    pub(crate) wall: Option<u32>,
}

/// relief's own functions: nothing counted, the textures at their own names and bindings, the
/// edge mode from `Params`, samples at the level `lod` asks for.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct Plain {
    /// The pipeline's `lod`.
    pub(crate) lod: Lod,
    /// The safe marches gather their cells' corners instead of reading the patch map
    /// ([`Policy::cell_patches`]).
    pub(crate) gather_patches: bool,
}

impl Policy for Plain {
    fn lod(&self) -> Lod {
        self.lod
    }
    fn cell_patches(&self) -> bool {
        !self.gather_patches
    }
}

/// The probe's copy of a function: `inner`'s decisions, with loop passes counted in `steps`
/// and every texture fetch in [`super::counter::FETCHES`].
pub(crate) struct Counting<'p> {
    /// The policy this one counts for.
    pub(crate) inner: &'p dyn Policy,
    /// The counter a loop pass adds one to.
    pub(crate) steps: &'static str,
}

impl Policy for Counting<'_> {
    fn step_counter(&self) -> Option<&'static str> {
        Some(self.steps)
    }
    fn lod(&self) -> Lod {
        self.inner.lod()
    }
    fn edge_clamp_constant(&self) -> Option<Handle<naga::Constant>> {
        self.inner.edge_clamp_constant()
    }
    fn texture(&self, name: &str, binding: u32) -> TextureSite {
        self.inner.texture(name, binding)
    }
    fn quadric_warp(&self) -> bool {
        self.inner.quadric_warp()
    }
    fn prism_lift(&self) -> bool {
        self.inner.prism_lift()
    }
    fn prism_untilted(&self) -> bool {
        self.inner.prism_untilted()
    }
    fn layer_share(&self) -> bool {
        self.inner.layer_share()
    }
    fn cell_patches(&self) -> bool {
        self.inner.cell_patches()
    }
}
