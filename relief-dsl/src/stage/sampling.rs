//! How stages read the maps: textures and samplers declared on first use, 2D samples at the
//! pipeline's level (`lod`), gathers, texel loads, the 3D distance field, the height map's
//! size and levels, the `Params` fields and the edge mode, with the probe's fetch count and
//! lavapipe's level work-arounds. Stage bodies call these and never write a sample by hand.

use naga::{Expression, ImageClass, ImageDimension, SampleLevel, ScalarKind, TypeInner};

use crate::abi::{binding, Param, Params};
pub use crate::ir::Filter;
use crate::ir::{FnBuilder, Image, IntoVal, Resource, Val, Vec2, Vec3, Vec4};
use crate::spec::MapReq;

/// The float texture of `image` of dimension `dim` (`arrayed`: an array of layers), declared
/// on first use for reads through the sampler of `filter`: under its own name and binding
/// for [`Filter::Linear`] (also what texel loads and size queries read), as `NAME_nearest` at
/// [`binding::NEAREST_OFFSET`] more for [`Filter::Nearest`]; the function's policy may move
/// it (a room's wall reads its own copy). The module's binding table records which it is.
fn texture_of(
    s: &FnBuilder<'_>,
    image: Image,
    filter: Filter,
    dim: ImageDimension,
    arrayed: bool,
) -> naga::Handle<naga::GlobalVariable> {
    let (name, plain) = match filter {
        Filter::Linear => (image.texture_name(), image.binding()),
        Filter::Nearest => (format!("{}_nearest", image.texture_name()), image.binding() + binding::NEAREST_OFFSET),
    };
    let site = s.policy().texture(&name, plain);
    let resource = Resource::Texture { image, filter, wall: site.wall };
    s.module().bound(&site.name, naga::AddressSpace::Handle, site.binding, resource, |m| {
        m.ty(TypeInner::Image { dim, arrayed, class: ImageClass::Sampled { kind: ScalarKind::Float, multi: false } })
    })
}

/// The 2D float texture of `image` for reads through `filter`, declared on first use.
fn texture_2d(s: &FnBuilder<'_>, image: Image, filter: Filter) -> naga::Handle<naga::GlobalVariable> {
    texture_of(s, image, filter, ImageDimension::D2, false)
}

/// The private global that holds the mip level every 2D sample is taken at when the
/// pipeline's `lod` is not zero (a whole number as `f32`); the entry points store it before
/// they trace ([`crate::compose`]).
pub(crate) const SAMPLE_LEVEL: &str = "relief_sample_level";

/// The private `f32` global [`SAMPLE_LEVEL`].
pub(crate) fn sample_level_global(m: &crate::ir::ModuleCtx) -> naga::Handle<naga::GlobalVariable> {
    m.private::<f32>(SAMPLE_LEVEL)
}

/// The private `vec2` global of the quadric's coefficients under `curved=quadric` (Oliveira &
/// Policarpo 2005; Szirmay-Kalos & Umenhoffer 2008, §5.1, eq. 13 with the mixed term 0 in the
/// frame of the principal directions): the reference surface lies
/// `a·Δu² + b·Δv²` (in units of the relief's depth, negative where the surface curves away
/// from its tangent plane) above the tangent plane of the point [`QUADRIC_ORIGIN`], Δ the
/// offset in texture coordinates from it. The mesh module's fragment stores both before it
/// traces.
pub(crate) const QUADRIC_COEFFS: &str = "relief_quadric";
/// The private `vec2` global of the texture point the quadric is centred on (the ray's
/// entry, then the hit for the shadow and ao stages).
pub(crate) const QUADRIC_ORIGIN: &str = "relief_quadric_origin";
/// The private `vec3` global of the lift every height read adds under `curved=prism` (in
/// units of the relief's depth), an affine function of the texture point:
/// `lift.x + lift.yz · (uv − origin)`, `origin` the private `vec2` [`PRISM_ORIGIN`]. The
/// fragment's search runs on the chord from the prism's exact entry to its exact exit, which
/// in texture space need not descend as the stages' rays do (from height 1, `dir.z = −1`):
/// with every height raised by the difference between the stages' ray and the chord at the
/// same texture point, the stages' ray meets the raised field exactly where the chord meets
/// the true one (docs/meshes-shaders.md). The mesh module's fragment stores both before the
/// search and sets the lift back to 0 after (shadow and ao read the true heights).
pub(crate) const PRISM_LIFT: &str = "relief_prism_lift";
/// The private `vec2` global of the texture point the prism's lift ([`PRISM_LIFT`]) is
/// centred on: the chord's entry.
pub(crate) const PRISM_ORIGIN: &str = "relief_prism_origin";
/// The private `vec4` global of the prism chord's bend under `curved=prism` where the chord is
/// searched tilted (the coarse stage reads no map, `Policy::prism_untilted` false): xy the
/// texture offset and z the layer offset of the view ray's exact point through the prism at
/// the chord's middle from the chord's own middle, w unused. The view ray through the prism's
/// map is a curve in texture space; the search follows the quadratic through its entry, its
/// exact middle and its exit: a height read at the chord's texture point `uv`, a fraction
/// `s = (uv − origin)·axis` ([`PRISM_BEND_AXIS`]) of the way from the entry, reads the height
/// at `uv + xy·β` and compares it with a layer `z·β` lower, `β = max(0, 4s(1 − s))`
/// (docs/meshes-shaders.md). The mesh module's fragment stores it with the lift and sets it
/// back to 0 after the search.
pub(crate) const PRISM_BEND: &str = "relief_prism_bend";
/// The private `vec2` global that turns a chord's texture point into its fraction of the
/// chord ([`PRISM_BEND`]): `Δuv / |Δuv|²`, Δuv the chord's texture-space length, or 0 for a
/// chord too short in texture space to bend.
pub(crate) const PRISM_BEND_AXIS: &str = "relief_prism_bend_axis";
/// The private `f32` global of where a cell march ends under `curved=prism` where the coarse
/// stage reads maps (`Policy::prism_untilted`): the t of the end of the straight piece of the
/// bent chord being searched (`compose::mesh`'s piece search), or 0 for no end but the floor.
/// A march that reaches it reports it as it reports the floor; the mesh module's fragment
/// tells the two apart (the point there lies above the surface) and sets it back to 0 after
/// the search, before the shadow and ao stages march.
pub(crate) const PRISM_STOP: &str = "relief_prism_stop";

/// The prism chord's bend's weight at the fraction `f` of the chord (0 at the entry, 1 at the
/// exit): `max(0, 4f(1 − f))`, the quadratic that is 1 at the middle and 0 at both ends
/// ([`PRISM_BEND`]); the reads and the hit the mesh module carries take the same.
pub(crate) fn bend_weight<'a>(f: Val<'a, f32>) -> Val<'a, f32> {
    (f * (1.0 - f) * 4.0).max(0.0)
}

/// The private `f32` global of the share of the relief's layers a linear search takes
/// where the policy asks ([`crate::ir::Policy::layer_share`]): the prism walk searches
/// each prism's chord over the stages' whole t from 0 to 1, and the chord's share (its drop,
/// in units of the relief's depth, or the drop a flat tile would give its length in texture
/// space, whichever is larger; at most 1) sets how many of the search's layers it gets, so
/// that a ray crossing several prisms is sampled as densely as on the flat tile and not once
/// per prism. The walk stores it before each search and sets it back to 1 after.
pub(crate) const LAYER_SHARE: &str = "relief_layer_share";

impl<'a> FnBuilder<'a> {
    /// The quadric's height at `uv` ([`QUADRIC_COEFFS`]) where the function's policy warps
    /// heights, else `None`. Warping the height field by the quadric is the survey's warping
    /// of the ray turned around (Szirmay-Kalos & Umenhoffer 2008, §5.1: the ray's height
    /// above the curved surface is its height above the tangent plane less the quadric's),
    /// so every stage keeps its straight ray and its algorithm box.
    fn quadric_at(&'a self, uv: Val<'a, Vec2>) -> Option<Val<'a, f32>> {
        if !self.policy().quadric_warp() {
            return None;
        }
        let m = self.module();
        let c = self.load::<Vec2>(self.global_ptr(m.private::<Vec2>(QUADRIC_COEFFS)));
        let o = self.load::<Vec2>(self.global_ptr(m.private::<Vec2>(QUADRIC_ORIGIN)));
        let d = uv - o;
        Some(c.x() * d.x() * d.x() + c.y() * d.y() * d.y())
    }

    /// The prism's lift at `uv` ([`PRISM_LIFT`]) where the function's policy lifts heights,
    /// else `None`.
    fn lift(&'a self, uv: Val<'a, Vec2>) -> Option<Val<'a, f32>> {
        if !self.policy().prism_lift() {
            return None;
        }
        let m = self.module();
        let l = self.load::<Vec3>(self.global_ptr(m.private::<Vec3>(PRISM_LIFT)));
        let o = self.load::<Vec2>(self.global_ptr(m.private::<Vec2>(PRISM_ORIGIN)));
        Some(l.x() + self.vec2(l.y(), l.z()).dot(uv - o))
    }

    /// Where a height read at the chord's texture point `uv` reads under the prism chord's
    /// bend ([`PRISM_BEND`]), and the layer offset it compares with (subtracted from the
    /// height), where the function's policy bends the chord (it lifts heights and the
    /// chord is searched tilted); else `None`.
    fn bend(&'a self, uv: Val<'a, Vec2>) -> Option<(Val<'a, Vec2>, Val<'a, f32>)> {
        if !self.policy().prism_lift() || self.policy().prism_untilted() {
            return None;
        }
        let m = self.module();
        let b = self.load::<Vec4>(self.global_ptr(m.private::<Vec4>(PRISM_BEND)));
        let axis = self.load::<Vec2>(self.global_ptr(m.private::<Vec2>(PRISM_BEND_AXIS)));
        let o = self.load::<Vec2>(self.global_ptr(m.private::<Vec2>(PRISM_ORIGIN)));
        let f = (uv - o).dot(axis);
        let beta = bend_weight(f);
        Some((uv + b.xy() * beta, b.z() * beta))
    }

    /// Where a cell march along `ray` ends: at the floor (`t_max`), or earlier at the end of
    /// the prism chord's piece being searched where the policy searches pieces
    /// (`Policy::prism_untilted`, [`PRISM_STOP`], 0 for none).
    pub(crate) fn march_end(&'a self, t_max: Val<'a, f32>) -> Val<'a, f32> {
        if !self.policy().prism_lift() || !self.policy().prism_untilted() {
            return t_max;
        }
        let stop = self.load::<f32>(self.global_ptr(self.module().private::<f32>(PRISM_STOP)));
        self.select(stop.gt(0.0), t_max.min(stop), t_max)
    }

    /// A height read from a map other than the height map (a bilinear cell's apex `A_C` stored
    /// in its cell map, a max-mip node's maximum), raised as every read of the height map is
    /// under the prism's lift (`PRISM_LIFT`): the map bounds the unlifted field, and the
    /// stages compare it with a ray that descends over the lifted one. Raised by the lift's
    /// constant term only, which is the whole lift where the pipeline's coarse stage reads maps
    /// (`Policy::prism_untilted`: the mesh module searches only the descending straight pieces
    /// of the bent chord with the stages, each untilted): a vertical shift keeps every cone
    /// and every maximum a bound, so cone ratios and distances need no change. Without the
    /// lift, `h` unchanged.
    pub fn map_height(&'a self, h: Val<'a, f32>) -> Val<'a, f32> {
        if !self.policy().prism_lift() {
            return h;
        }
        let m = self.module();
        let l = self.load::<Vec3>(self.global_ptr(m.private::<Vec3>(PRISM_LIFT)));
        h + l.x()
    }

    /// A linear search's layer count `n` (whole, ≥ 1) scaled by the chord's share of the
    /// layers ([`LAYER_SHARE`]) where the policy asks: `ceil(n·share)` clamped to `1..=max`;
    /// else `None`, and the search keeps its own count.
    pub(crate) fn shared_layers(&'a self, n: impl IntoVal<'a, f32>, max: u32) -> Option<Val<'a, f32>> {
        if !self.policy().layer_share() {
            return None;
        }
        let n = n.into_val(self);
        let share = self.load::<f32>(self.global_ptr(self.module().private::<f32>(LAYER_SHARE)));
        Some((n * share).ceil().clamp(1.0, max as f32))
    }

    /// The level 2D samples are taken at: `None` under `lod=zero` (level 0, the explicit
    /// `SampleLevel::Zero` of every sample before the option), else the stage-wide level in
    /// [`SAMPLE_LEVEL`]. Stage bodies never see it: every sampling method below reads it.
    pub(crate) fn sample_level(&'a self) -> Option<Val<'a, f32>> {
        if self.policy().lod() == crate::spec::Lod::Zero {
            return None;
        }
        let g = sample_level_global(self.module());
        Some(self.load(self.global_ptr(g)))
    }

    /// The sampler of `filter` (declared on first use).
    pub(crate) fn sampler_global(&'a self, filter: Filter) -> naga::Handle<naga::GlobalVariable> {
        let (sname, sbind) = match filter {
            Filter::Linear => ("linear_sampler", binding::LINEAR_SAMPLER),
            Filter::Nearest => ("nearest_sampler", binding::NEAREST_SAMPLER),
        };
        self.module().bound(sname, naga::AddressSpace::Handle, sbind, Resource::Sampler(filter), |m| {
            m.ty(TypeInner::Sampler { comparison: false })
        })
    }

    /// One `textureSample*` of `tex` through the sampler of `filter`; `counted`: it counts
    /// one fetch in the probe variant (a gather at a level counts its four samples once).
    pub(crate) fn image_sample(
        &'a self,
        tex: naga::Handle<naga::GlobalVariable>,
        coordinate: naga::Handle<Expression>,
        filter: Filter,
        gather: bool,
        level: SampleLevel,
        counted: bool,
    ) -> Val<'a, Vec4> {
        // The sampler is declared before the counter is touched, as it always was, so that
        // globals keep their order in the emitted module.
        let smp = self.sampler_global(filter);
        if counted && self.counting() {
            self.count(crate::ir::counter::FETCHES);
        }
        let image = self.expr(Expression::GlobalVariable(tex));
        let sampler = self.expr(Expression::GlobalVariable(smp));
        self.wrap(self.expr(Expression::ImageSample {
            image,
            sampler,
            gather: gather.then_some(naga::SwizzleComponent::X),
            coordinate,
            array_index: None,
            offset: None,
            level,
            depth_ref: None,
            clamp_to_edge: false,
        }))
    }

    /// A 2D sample at the stage-wide level ([`FnBuilder::sample_level`]).
    pub(crate) fn sample_2d(
        &'a self,
        tex: naga::Handle<naga::GlobalVariable>,
        uv: Val<'a, Vec2>,
        filter: Filter,
    ) -> Val<'a, Vec4> {
        let level = match self.sample_level() {
            None => SampleLevel::Zero,
            Some(l) => SampleLevel::Exact(l.handle()),
        };
        self.image_sample(tex, uv.handle(), filter, false, level, true)
    }

    /// The first channel of the four texels a bilinear sample of `image` at `uv` blends, in
    /// gather order, at the stage-wide level.
    ///
    /// WGSL's `textureGather` has no level argument (it reads level 0), so at a level other
    /// than zero the four texels are read one by one: with `(w, h)` the level's size, the
    /// lower-left texel is `(i, j) = floor(uv·(w, h) − ½)`, and each of `(i, j+1), (i+1, j+1),
    /// (i+1, j), (i, j)` is a nearest sample at its texel centre on that level, so the
    /// sampler applies the edge mode exactly as the bilinear sample does. The level's size
    /// comes from [`FnBuilder::level_size`], not from `textureDimensions` at the level: the level
    /// differs between neighbouring rays under `lod=auto`, and lavapipe answers
    /// `textureDimensions` at such a level with another lane's level (measured: safe CSM rays
    /// ended up to 0.46 in t past the first hit where neighbouring pixels sampled different
    /// levels, while the same rays at one fixed level were exact; `textureLoad` at such a
    /// level is right). The probe counts the four as one fetch, the one gather they stand
    /// for, so that fetch counts compare across levels.
    pub(crate) fn gather_2d(&'a self, image: Image, uv: Val<'a, Vec2>) -> Val<'a, Vec4> {
        let Some(level) = self.sample_level() else {
            let tex = texture_2d(self, image, Filter::Linear);
            return self.image_sample(tex, uv.handle(), Filter::Linear, true, SampleLevel::Zero, true);
        };
        if self.counting() {
            self.count(crate::ir::counter::FETCHES);
        }
        let tex = texture_2d(self, image, Filter::Nearest);
        let size = self.level_size(image, level);
        let base = (uv * size - 0.5).floor();
        let texel = |dx: f32, dy: f32| -> Val<'a, f32> {
            let centre = (base + self.vec2(dx + 0.5, dy + 0.5)) / size;
            self.image_sample(tex, centre.handle(), Filter::Nearest, false, SampleLevel::Exact(level.handle()), false)
                .x()
        };
        let (a, b, c, d) = (texel(0.0, 1.0), texel(1.0, 1.0), texel(1.0, 0.0), texel(0.0, 0.0));
        self.vec4(self.vec3(self.vec2(a, b), c), d)
    }

    /// The size in texels of level `level` of `image` (as floats): level 0's size
    /// halved `level` times, exact because every level of relief's chains is half the one
    /// before (`maps::mips` stops before an odd side). Not `textureDimensions` at the level,
    /// which lavapipe gets wrong when the level differs between lanes (see [`FnBuilder::gather_2d`]).
    pub(crate) fn level_size(&'a self, image: Image, level: Val<'a, f32>) -> Val<'a, Vec2> {
        let tex = texture_2d(self, image, Filter::Linear);
        let image = self.expr(Expression::GlobalVariable(tex));
        let zero = self.lit_u32(0).handle();
        let size = self.expr(Expression::ImageQuery { image, query: naga::ImageQuery::Size { level: Some(zero) } });
        let size0: Val<'a, Vec2> =
            self.wrap(self.expr(Expression::As { expr: size, kind: ScalarKind::Float, convert: Some(4) }));
        size0 * (-level).exp2()
    }

    /// Samples `image` at `uv`, at the stage-wide level (explicit, so sampling is valid in
    /// any control flow). Counts one fetch in the probe variant.
    ///
    /// An image read with nearest filtering is declared a second time, as `NAME_nearest` at
    /// binding [`binding::NEAREST_OFFSET`] + its binding (the runtime binds the same texture
    /// to both): GLSL combines textures with samplers, and one texture read through two
    /// samplers has no GLSL form.
    pub(crate) fn sample(&'a self, image: Image, uv: Val<'a, Vec2>, filter: Filter) -> Val<'a, Vec4> {
        let tex = texture_2d(self, image, filter);
        self.sample_2d(tex, uv, filter)
    }

    /// Samples a precomputed map (all channels).
    pub fn map(&'a self, map: MapReq, uv: Val<'a, Vec2>, filter: Filter) -> Val<'a, Vec4> {
        self.no_level_map(map);
        self.sample(Image::of(map), uv, filter)
    }

    /// The smallest of the four texels around `uv` in the map's first channel (one gather):
    /// what a bilinear sample at `uv` can never undercut.
    pub fn map_min4(&'a self, map: MapReq, uv: Val<'a, Vec2>) -> Val<'a, f32> {
        let g = self.map_gather(map, uv);
        g.x().min(g.y()).min(g.z().min(g.w()))
    }

    /// The first channel of the four texels a bilinear sample at `uv` blends (one gather), in
    /// gather order: `(i, j+1), (i+1, j+1), (i+1, j), (i, j)` with `(i, j)` the lower-left
    /// texel.
    pub fn map_gather(&'a self, map: MapReq, uv: Val<'a, Vec2>) -> Val<'a, Vec4> {
        self.no_level_map(map);
        self.gather_2d(Image::of(map), uv)
    }

    /// The four heights a bilinear sample at `uv` blends (see [`FnBuilder::map_gather`]), at the
    /// stage-wide level.
    pub fn height_gather(&'a self, uv: Val<'a, Vec2>) -> Val<'a, Vec4> {
        let g = match self.bend(uv) {
            Some((at, drop)) => self.gather_2d(Image::Height, at) - drop.splat::<Vec4>(),
            None => self.gather_2d(Image::Height, uv),
        };
        let g = match self.quadric_at(uv) {
            // The four corners take the quadric at `uv`, not at their own texel centres: an
            // approximation that moves a corner by at most the quadric's change over one
            // texel (docs/meshes-shaders.md).
            Some(q) => g + q.splat::<Vec4>(),
            None => g,
        };
        match self.lift(uv) {
            Some(l) => g + l.splat::<Vec4>(),
            None => g,
        }
    }

    /// A height of the height map raised as every read of it is (the `h00` of a cell's patch
    /// in the patch map, [`MapReq::CellPatch`], or a bilinear sample), as [`FnBuilder::height_gather`] raises the
    /// four corners it gathers at `uv`: by the quadric, then by the prism's lift, both taken
    /// at `uv` for all four corners. So a patch read from the patch map is the gathered one
    /// raised by one constant, which leaves its differences unchanged (and, without a
    /// quadric or a lift, it is the gathered patch bit for bit).
    pub fn height_raised_at(&'a self, h: Val<'a, f32>, uv: Val<'a, Vec2>) -> Val<'a, f32> {
        let h = match self.quadric_at(uv) {
            Some(q) => h + q,
            None => h,
        };
        match self.lift(uv) {
            Some(l) => h + l,
            None => h,
        }
    }

    /// Only maps with a mip chain of their own level's data ([`MapReq::has_levels`]) may be
    /// read at a level: every other map is built over level 0 of the height map (cells, the
    /// max-mip pyramid), so reading it at another level would mix two surfaces; it is
    /// refused under a `lod` other than zero.
    pub(crate) fn no_level_map(&'a self, map: MapReq) {
        if !map.has_levels() {
            self.no_level(map.name());
        }
    }

    /// The texel `coords` of mip level `level` of a map (no filtering).
    ///
    /// Under a `lod` other than zero only the max-mip pyramid has a form per level: the
    /// runtime uploads the pyramid of every level of the height map's chain as the layers of
    /// one array texture (layer k: the pyramid over level k's cells, its level j in the
    /// top-left of mip j), so the read takes layer k, the stage-wide level, and the
    /// pyramid's level `level` as the mip (`textureLoad` at a lane-varying mip is right on
    /// lavapipe; `textureDimensions` is not, see the private `gather_2d`). Any other map is
    /// refused there: its texels are level-0 cells.
    pub fn map_texel(&'a self, map: MapReq, coords: Val<'a, crate::ir::UVec2>, level: Val<'a, u32>) -> Val<'a, Vec4> {
        let layer = match self.sample_level() {
            Some(l) if map == MapReq::MaxMip => Some(l.to_u32()),
            _ => {
                self.no_level(map.name());
                None
            }
        };
        let tex = texture_of(self, Image::of(map), Filter::Linear, ImageDimension::D2, layer.is_some());
        if self.counting() {
            self.count(crate::ir::counter::FETCHES);
        }
        let image = self.expr(Expression::GlobalVariable(tex));
        self.wrap(self.expr(Expression::ImageLoad {
            image,
            coordinate: coords.handle(),
            array_index: layer.map(|l| l.handle()),
            sample: None,
            level: Some(level.handle()),
        }))
    }

    /// Samples the 3D distance field at `(u, v, height)`, trilinear.
    pub fn distance(&'a self, p: Val<'a, Vec3>) -> Val<'a, f32> {
        let map = MapReq::DistanceField;
        self.no_level(map.name());
        let tex = texture_of(self, Image::Map(map), Filter::Linear, ImageDimension::D3, false);
        // Under the prism's lift the field is the unlifted surface's: the lifted surface lies
        // as far from p as the unlifted one from p lowered by the lift ([`FnBuilder::map_height`]).
        let p = if self.policy().prism_lift() { self.vec3(p.xy(), p.z() - self.map_height(self.lit(0.0))) } else { p };
        self.image_sample(tex, p.handle(), Filter::Linear, false, SampleLevel::Zero, true).x()
    }

    /// The size in texels of level 0 of `image`, declared for reads through `filter` (as
    /// floats). Level 0 only: under a `lod` the maps of all levels share one atlas, whose
    /// size is no level's.
    pub(crate) fn image_size(&'a self, image: Image, filter: Filter) -> Val<'a, Vec2> {
        let tex = texture_2d(self, image, filter);
        let image = self.expr(Expression::GlobalVariable(tex));
        let level = self.lit_u32(0).handle();
        let size = self.expr(Expression::ImageQuery { image, query: naga::ImageQuery::Size { level: Some(level) } });
        self.wrap(self.expr(Expression::As { expr: size, kind: ScalarKind::Float, convert: Some(4) }))
    }

    /// The size of level 0 of the height map in texels, as floats (its users address level-0
    /// cells, and read maps that [`FnBuilder::map_texel`] refuses at another level).
    pub fn height_map_size(&'a self) -> Val<'a, Vec2> {
        match self.sample_level() {
            None => self.image_size(Image::Height, Filter::Linear),
            Some(l) => self.level_size(Image::Height, l),
        }
    }

    /// The entry of cell `index` in the cell map `map` (one load, no filtering), for the cells
    /// of the level the stage samples.
    ///
    /// Under a `lod` other than zero the runtime uploads a cell map as an atlas of the cell
    /// maps of every level of the height map's chain, stacked by rows from level 0 down, each
    /// at the left edge (cells of a level: `w_k × h_k` under repeat, `(w_k + 1) × (h_k + 1)`
    /// under clamp, see `stage::coarse::cell`). Every level of the chain is half the one
    /// before (the chain stops before an odd side), so the rows above level k number
    /// `Σ_{j<k} h_j = 2·h_0 − 2·h_k`, plus k under clamp: the cell's row is offset by that.
    ///
    /// A map of 2 × 2 texels a cell ([`MapReq::cell_texels`], the quad cone map) is read at
    /// `2·(cell's texel) + quadrant`, its atlas stacked the same way in its own texels.
    pub fn cell_map_texel(
        &'a self,
        map: MapReq,
        index: Val<'a, Vec2>,
        quadrant: Option<Val<'a, Vec2>>,
    ) -> Val<'a, Vec4> {
        let tex = texture_2d(self, Image::of(map), Filter::Linear);
        if self.counting() {
            self.count(crate::ir::counter::FETCHES);
        }
        let cell = match self.sample_level() {
            None => index,
            Some(l) => {
                let hk = self.level_size(Image::Height, l).y();
                let h0 = hk * l.exp2();
                let borders = self.select(self.edge_is_clamp(), l, self.lit(0.0));
                let rows = h0 * 2.0 - hk * 2.0 + borders;
                self.vec2(index.x(), index.y() + rows)
            }
        };
        let coords = match quadrant {
            None => cell.to_u32(),
            Some(q) => cell.mul_add(2.0, q).to_u32(),
        };
        let image = self.expr(Expression::GlobalVariable(tex));
        let level = self.lit_u32(0);
        self.wrap(self.expr(Expression::ImageLoad {
            image,
            coordinate: coords.handle(),
            array_index: None,
            sample: None,
            level: Some(level.handle()),
        }))
    }

    /// The number of mip levels of the height map, as a float.
    pub(crate) fn height_map_levels(&'a self) -> Val<'a, f32> {
        let tex = texture_2d(self, Image::Height, Filter::Linear);
        let image = self.expr(Expression::GlobalVariable(tex));
        let n = self.expr(Expression::ImageQuery { image, query: naga::ImageQuery::NumLevels });
        self.wrap(self.expr(Expression::As { expr: n, kind: ScalarKind::Float, convert: Some(4) }))
    }

    /// GETHEIGHT of the algorithm boxes: the height map at `uv`, bilinear.
    pub fn height(&'a self, uv: Val<'a, Vec2>) -> Val<'a, f32> {
        let h = match self.bend(uv) {
            Some((at, drop)) => self.sample(Image::Height, at, Filter::Linear).x() - drop,
            None => self.sample(Image::Height, uv, Filter::Linear).x(),
        };
        self.height_raised_at(h, uv)
    }

    /// The member `p` of the `Params` uniform block ([`crate::abi::Params`]).
    pub(crate) fn param<T: crate::ir::Ty>(&'a self, p: Param) -> Val<'a, T> {
        let g = self.module().bound("params", naga::AddressSpace::Uniform, binding::PARAMS, Resource::Params, |m| {
            m.record_ty::<Params>()
        });
        self.load(self.member_ptr::<Params>(self.global_ptr(g), p.name()))
    }

    /// Whether the scene's edge mode is clamp (`params.quad.y` is 1), for stages that address
    /// texels themselves.
    pub fn edge_is_clamp(&'a self) -> Val<'a, bool> {
        if let Some(c) = self.policy().edge_clamp_constant() {
            return self.wrap(self.expr(Expression::Constant(c)));
        }
        self.param::<Vec4>(Param::Quad).y().gt(0.5)
    }

    /// The tangent-space normal at `uv`, from the normal map (stored `n * 0.5 + 0.5`).
    pub fn normal(&'a self, uv: Val<'a, Vec2>) -> Val<'a, Vec3> {
        let n = self.sample(Image::Normal, uv, Filter::Linear).xyz();
        (n * 2.0 - 1.0).normalize()
    }
}
