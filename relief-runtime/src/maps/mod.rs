//! Precomputed acceleration maps, one file per kind.
//!
//! Units shared by every kind: heights in [0, 1] (1 = top), texel `(x, y)` a point sample at
//! `((x + .5) / width, (y + .5) / height)`, horizontal distances in texture coordinates (the
//! map spans [0, 1] in u and v; with [`EdgeMode::Repeat`] the shorter way round). A cone ratio
//! is horizontal distance over height difference (GPU Gems 3 ch. 18). f32 maps are not
//! clamped (a cone with nothing above it is `+inf`); only an [`encode::Encoding`] clamps.
//!
//! Entry points: [`build`] one map kind from a height map, [`MapCache`] to build each
//! (height map, kind, parameters, edge mode, encoding) once, [`file::write_map`] to save.
pub mod cell;
pub mod cone;
pub mod cone_normal;
pub mod distance_field;
pub mod encode;
pub mod file;
pub mod filter;
pub mod max_mip;
pub mod mips;
pub mod multi_cone;
pub mod normal;
pub mod quad_cone;
pub mod relaxed_cone;
pub mod search;

use crate::heightmap::{EdgeMode, HeightMap};
use encode::{EncodedMap, Encoding, Rounding};
use relief_dsl::spec::MapReq;
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};

/// The map kinds, by the names the CLI and the pipeline specs use.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum MapKind {
    /// `cone`: conservative cone ratio (1 channel), [`cone`].
    Cone,
    /// `quad_cone`: four quadrant cone ratios (4 channels), [`quad_cone`].
    QuadCone,
    /// `relaxed_cone`: relaxed cone ratio (1 channel), [`relaxed_cone`].
    RelaxedCone,
    /// `cone_normal`: `n_z` of the conservative cone (1 channel), [`cone_normal`].
    ConeNormal,
    /// `relaxed_cone_normal`: `n_z` of the relaxed cone (1 channel), [`cone_normal`].
    RelaxedConeNormal,
    /// `multi_cone`: `n_z` of K stacked cones (K channels), [`multi_cone`] method 1.
    MultiCone,
    /// `piecewise_cone`: `n_z` of K piecewise cone slopes (K channels), [`multi_cone`] method 2.
    PiecewiseCone,
    /// `max_mip`: maximum-height pyramid over the bilinear cells (1 channel, mip levels in
    /// [`Map::mips`]), [`max_mip`].
    MaxMip,
    /// `distance_field`: 3D distance to the surface (1 channel, `depth` = z resolution),
    /// [`distance_field`].
    DistanceField,
    /// `cell_cone`: per bilinear cell `[ratio, apex]` (2 channels, cell grid), [`cell::cone`].
    CellCone,
    /// `cell_quad_cone`: per cell 4 quadrant ratios, each with the apex (2 × 2 texels of 2
    /// channels a cell), [`cell::cone`].
    CellQuadCone,
    /// `cell_relaxed_cone`: per cell `[relaxed ratio, apex]` (2 channels), [`cell::relaxed_cone`].
    CellRelaxedCone,
    /// `cell_cone_normal`: per cell `[n_z, apex]` (2 channels), [`cell::cone`].
    CellConeNormal,
    /// `cell_multi_cone`: per cell K stacked-cone `n_z` + apex (K + 1 channels), [`cell::multi_cone`].
    CellMultiCone,
    /// `cell_piecewise_cone`: per cell K piecewise slopes as `n_z` + apex (K + 1 channels),
    /// [`cell::multi_cone`].
    CellPiecewiseCone,
    /// `cell_patch`: per cell the bilinear patch's coefficients `[h00, h10 − h00, h01 − h00,
    /// (h11 − h10) − (h01 − h00)]` (4 channels, cell grid), [`cell::patch`].
    CellPatch,
}

impl MapKind {
    /// Every kind, in the order `relief maps --list` prints them.
    pub const ALL: [MapKind; 16] = [
        MapKind::Cone,
        MapKind::QuadCone,
        MapKind::RelaxedCone,
        MapKind::ConeNormal,
        MapKind::RelaxedConeNormal,
        MapKind::MultiCone,
        MapKind::PiecewiseCone,
        MapKind::MaxMip,
        MapKind::DistanceField,
        MapKind::CellCone,
        MapKind::CellQuadCone,
        MapKind::CellRelaxedCone,
        MapKind::CellConeNormal,
        MapKind::CellMultiCone,
        MapKind::CellPiecewiseCone,
        MapKind::CellPatch,
    ];

    /// The map request this kind answers (with the default parameters): see
    /// [`MapKind::request_with`].
    pub fn request(self) -> MapReq {
        self.request_with(&MapParams::default())
    }

    /// The map request this kind answers with `params`: the one table between the two enums,
    /// [`MapKind::of`] reads it backwards. What the request says of the map (its channels,
    /// whether it is a cell map) is stated there, in relief-dsl.
    pub fn request_with(self, params: &MapParams) -> MapReq {
        let k = params.cones;
        match self {
            MapKind::Cone => MapReq::Cone,
            MapKind::QuadCone => MapReq::QuadCone,
            MapKind::RelaxedCone => MapReq::RelaxedCone,
            MapKind::ConeNormal => MapReq::ConeNormal,
            MapKind::RelaxedConeNormal => MapReq::RelaxedConeNormal,
            MapKind::MultiCone => MapReq::MultiCone(k),
            MapKind::PiecewiseCone => MapReq::PiecewiseCone(k),
            MapKind::MaxMip => MapReq::MaxMip,
            MapKind::DistanceField => MapReq::DistanceField,
            MapKind::CellCone => MapReq::CellCone,
            MapKind::CellQuadCone => MapReq::CellQuadCone,
            MapKind::CellRelaxedCone => MapReq::CellRelaxedCone,
            MapKind::CellConeNormal => MapReq::CellConeNormal,
            MapKind::CellMultiCone => MapReq::CellMultiCone(k),
            MapKind::CellPiecewiseCone => MapReq::CellPiecewiseCone(k),
            MapKind::CellPatch => MapReq::CellPatch,
        }
    }

    /// The kind and parameters behind a map request; `None` for [`MapReq::Normal`], which is
    /// not built here but uploaded with the scene ([`normal`]).
    pub fn of(req: MapReq) -> Option<(MapKind, MapParams)> {
        let same = |k: &MapKind| std::mem::discriminant(&k.request()) == std::mem::discriminant(&req);
        let kind = MapKind::ALL.into_iter().find(same)?;
        let d = MapParams::default();
        let params = match req.cones() {
            Some(k) => MapParams { cones: k, ..d },
            None => d,
        };
        Some((kind, params))
    }

    /// The name used on the command line and in specs: the request's name
    /// ([`MapReq::name`]).
    pub fn name(self) -> &'static str {
        self.request().name()
    }

    /// One line: what the map holds, its channels and the parameters it reads.
    pub fn describe(self) -> &'static str {
        match self {
            MapKind::Cone => "conservative cone ratio (Dummer 2006, CSM); 1 channel; +inf where nothing is higher",
            MapKind::QuadCone => "conservative cone ratio per quadrant of ray direction (QCSM; Policarpo & Oliveira 2007); 4 channels: +u+v, -u+v, -u-v, +u-v",
            MapKind::RelaxedCone => "relaxed cone ratio (Policarpo & Oliveira 2007, Listing 18-1); 1 channel",
            MapKind::ConeNormal => "n_z of the conservative cone side (Burger 2018 §3.1), r / sqrt(1 + r^2); 1 channel",
            MapKind::RelaxedConeNormal => "n_z of the relaxed cone side (Burger 2018 §3.1); 1 channel",
            MapKind::MultiCone => "n_z of K stacked cones, apexes at h + (1-h) k/K (Burger 2018 §3.4 method 1); K channels; param cones=K",
            MapKind::PiecewiseCone => "n_z of K piecewise cone slopes over [h + (1-h) k/K, h + (1-h)(k+1)/K] (Burger 2018 §3.4 method 2); K channels; param cones=K",
            MapKind::MaxMip => "maximum-height pyramid over bilinear cells (Tevs et al. 2008); 1 channel + mip levels",
            MapKind::DistanceField => "3D distance lower bound to the bilinear surface, safe under trilinear filtering (Donnelly 2005); width x height x z_resolution; param z_resolution",
            MapKind::CellCone => "cone per bilinear cell, conservative for the bilinear surface; cell grid (w x h repeat, (w+1) x (h+1) clamp); 2 channels: ratio, apex",
            MapKind::CellQuadCone => "quad-directional cone per bilinear cell, 2x2 texels a cell (2i+qx, 2j+qy; qx = 1 for a ray toward +u, qy = 1 toward +v); 2 channels: the quadrant's ratio, apex",
            MapKind::CellRelaxedCone => "relaxed cone per bilinear cell (at most one crossing inside the cone, proven rule); 2 channels: ratio, apex",
            MapKind::CellConeNormal => "n_z of the cell cone (Burger 2018 §3.1) per bilinear cell; 2 channels: n_z, apex",
            MapKind::CellMultiCone => "K stacked cell cones at apex + (1-apex) k/K as n_z (Burger 2018 §3.4 method 1); K+1 channels: n_z x K, apex; param cones=K",
            MapKind::CellPiecewiseCone => "K piecewise cell-cone slopes as n_z (Burger 2018 §3.4 method 2); K+1 channels: n_z x K, apex; param cones=K",
            MapKind::CellPatch => "bilinear patch coefficients per cell, in the shader's own order, read by the safe csm, cns, csm_relax and qcsm in place of a gather; cell grid; 4 channels: h00, h10-h00, h01-h00, (h11-h10)-(h01-h00); f32 only",
        }
    }

    /// Number of channels for `params` ([`MapReq::channels`] of the request).
    pub fn channels(self, params: &MapParams) -> usize {
        self.request_with(params).channels()
    }

    /// Whether the kind reads K, [`MapParams::cones`] ([`MapReq::cones`] of its request).
    pub fn reads_cones(self) -> bool {
        self.request().cones().is_some()
    }

    /// Whether this is a cell kind (map over the cell grid of [`cell`], last channel the apex:
    /// [`MapReq::is_cell`]).
    pub fn is_cell(self) -> bool {
        self.request().is_cell()
    }

    /// Whether the map holds one entry per bilinear cell (the cell kinds and `cell_patch`):
    /// [`MapReq::per_cell`].
    pub fn per_cell(self) -> bool {
        self.request().per_cell()
    }

    /// The safe quantisation direction of this kind's values: up for the heights of the
    /// max-mip pyramid, down for cone ratios, cone normals' `n_z` and distances (the cell
    /// maps' apex, a height, is rounded up apart: [`kind_rounding`]).
    pub fn rounding(self) -> Rounding {
        match self {
            MapKind::MaxMip => Rounding::Up,
            MapKind::Cone
            | MapKind::QuadCone
            | MapKind::RelaxedCone
            | MapKind::ConeNormal
            | MapKind::RelaxedConeNormal
            | MapKind::MultiCone
            | MapKind::PiecewiseCone
            | MapKind::DistanceField
            | MapKind::CellCone
            | MapKind::CellQuadCone
            | MapKind::CellRelaxedCone
            | MapKind::CellConeNormal
            | MapKind::CellMultiCone
            | MapKind::CellPiecewiseCone
            | MapKind::CellPatch => Rounding::Down,
        }
    }

    /// Whether the values are cone ratios (where the sqrt encoding is meant to be used).
    pub(crate) fn is_ratio(self) -> bool {
        match self {
            MapKind::Cone
            | MapKind::QuadCone
            | MapKind::RelaxedCone
            | MapKind::CellCone
            | MapKind::CellQuadCone
            | MapKind::CellRelaxedCone => true,
            MapKind::ConeNormal
            | MapKind::RelaxedConeNormal
            | MapKind::MultiCone
            | MapKind::PiecewiseCone
            | MapKind::MaxMip
            | MapKind::DistanceField
            | MapKind::CellConeNormal
            | MapKind::CellMultiCone
            | MapKind::CellPiecewiseCone
            | MapKind::CellPatch => false,
        }
    }
}

impl std::fmt::Display for MapKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

impl std::str::FromStr for MapKind {
    type Err = MapError;
    fn from_str(s: &str) -> Result<Self, MapError> {
        let s = s.trim().to_ascii_lowercase().replace('-', "_");
        MapKind::ALL.into_iter().find(|k| k.name() == s).ok_or_else(|| MapError::UnknownKind(s.to_string()))
    }
}

/// Parameters of the kinds that have any; every kind ignores the others.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct MapParams {
    /// K for `multi_cone` and `piecewise_cone` (1..=16).
    pub cones: u32,
    /// Number of z slices of `distance_field` (1..=1024).
    pub z_resolution: u32,
}

impl Default for MapParams {
    fn default() -> Self {
        MapParams { cones: 4, z_resolution: relief_dsl::abi::DISTANCE_FIELD_Z }
    }
}

impl MapParams {
    /// The parameters that matter to `kind` (others reset to defaults), for cache keys.
    pub(crate) fn relevant(&self, kind: MapKind) -> MapParams {
        let d = MapParams::default();
        match kind {
            MapKind::MultiCone | MapKind::PiecewiseCone | MapKind::CellMultiCone | MapKind::CellPiecewiseCone => {
                MapParams { cones: self.cones, ..d }
            }
            MapKind::DistanceField => MapParams { z_resolution: self.z_resolution, ..d },
            MapKind::Cone
            | MapKind::QuadCone
            | MapKind::RelaxedCone
            | MapKind::ConeNormal
            | MapKind::RelaxedConeNormal
            | MapKind::MaxMip
            | MapKind::CellCone
            | MapKind::CellQuadCone
            | MapKind::CellRelaxedCone
            | MapKind::CellConeNormal
            | MapKind::CellPatch => d,
        }
    }
}

/// Which map a request takes: its kind and the parameters that matter to that kind. Two
/// requests of one kind with different parameters are two maps.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct MapKey {
    /// The kind of map.
    pub kind: MapKind,
    /// Its parameters, reduced to those the kind reads (`MapParams::relevant`).
    pub params: MapParams,
}

impl MapKey {
    /// The key of a map request; `None` for [`MapReq::Normal`] (see [`MapKind::of`]).
    pub fn of(req: MapReq) -> Option<MapKey> {
        let (kind, params) = MapKind::of(req)?;
        Some(MapKey { kind, params: params.relevant(kind) })
    }
}

/// A built map: `width * height * depth * channels` f32 values, channels interleaved,
/// row-major (row y = v), slices (3D maps) outermost.
#[derive(Clone, Debug, PartialEq)]
pub struct Map {
    /// Entries per row: the height map's width for texel kinds; for the cell kinds the cell
    /// count ([`cell::CellGrid::cw`], one more under [`EdgeMode::Clamp`]).
    pub width: usize,
    /// Rows, counted like `width` ([`cell::CellGrid::ch`] for the cell kinds).
    pub height: usize,
    /// 1 for 2D maps; the z resolution for `distance_field`.
    pub depth: usize,
    /// Values per entry (see [`MapKind::channels`]).
    pub channels: usize,
    /// The values, `width * height * depth * channels` of them, laid out as said above;
    /// not clamped (a cone ratio can be `+inf`).
    pub data: Vec<f32>,
    /// Coarser levels for pyramid kinds (`max_mip`), level 1 first; empty otherwise.
    pub mips: Vec<Map>,
}

impl Map {
    /// A 2D map.
    pub fn new_2d(width: usize, height: usize, channels: usize, data: Vec<f32>) -> Map {
        debug_assert_eq!(data.len(), width * height * channels);
        Map { width, height, depth: 1, channels, data, mips: Vec::new() }
    }

    /// Value of channel `c` at texel `(x, y)` of slice `z`.
    pub fn get(&self, x: usize, y: usize, z: usize, c: usize) -> f32 {
        self.data[((z * self.height + y) * self.width + x) * self.channels + c]
    }

    /// One channel as its own single-channel map.
    pub fn channel(&self, c: usize) -> Map {
        Map {
            data: self.data.iter().skip(c).step_by(self.channels).copied().collect(),
            channels: 1,
            mips: Vec::new(),
            ..self.clone_shape()
        }
    }

    pub(crate) fn clone_shape(&self) -> Map {
        Map {
            width: self.width,
            height: self.height,
            depth: self.depth,
            channels: self.channels,
            data: Vec::new(),
            mips: Vec::new(),
        }
    }
}

/// Why a map could not be built or written.
#[derive(Debug, thiserror::Error)]
pub enum MapError {
    /// A name that is no [`MapKind`]; holds the name as compared: trimmed, lower-case, `-`
    /// turned into `_`.
    #[error("unknown map kind `{0}` (see `relief maps --list`)")]
    UnknownKind(String),
    /// The map cannot be built with these inputs: a parameter out of its range, an empty
    /// height map, or a kind that has no per-level form.
    #[error("bad parameter for {kind}: {message}")]
    Params {
        /// The kind being built.
        kind: MapKind,
        /// What is wrong.
        message: String,
    },
    /// Writing a `.npy` map file failed.
    #[error("{path}: cannot write: {source}")]
    Io {
        /// The file being written.
        path: PathBuf,
        /// The operating system's error.
        #[source]
        source: std::io::Error,
    },
    /// The map cannot be saved in this file: unknown extension, a format or a 3D map the
    /// file type cannot hold, or a `.png`/`.exr` writer error.
    #[error("{path}: {message}")]
    Output {
        /// The file being written.
        path: PathBuf,
        /// What is wrong.
        message: String,
    },
}

/// Builds one map of `kind` from `hm` (see each kind's module for the definition).
pub fn build(hm: &HeightMap, kind: MapKind, params: &MapParams, edge: EdgeMode) -> Result<Map, MapError> {
    let (w, h) = (hm.width, hm.height);
    if w == 0 || h == 0 || hm.data.len() != w * h {
        return Err(MapError::Params { kind, message: format!("height map {w} x {h} is empty or inconsistent") });
    }
    let k = params.cones as usize;
    if kind.reads_cones() && !(1..=16).contains(&k) {
        return Err(MapError::Params { kind, message: format!("cones = {k}, expected 1..=16") });
    }
    // The channels of every kind's texel, as relief-dsl states them (`MapReq::channels`).
    let n = kind.channels(params);
    let cells = |data: Vec<f32>| {
        let g = cell::CellGrid::new(w, h, edge);
        Map::new_2d(g.cw, g.ch, n, data)
    };
    let map = match kind {
        MapKind::Cone => Map::new_2d(w, h, n, cone::cone_ratios(hm, edge)),
        MapKind::QuadCone => Map::new_2d(w, h, n, quad_cone::quad_cone_ratios(hm, edge)),
        MapKind::RelaxedCone => Map::new_2d(w, h, n, relaxed_cone::relaxed_cone_ratios(hm, edge)),
        MapKind::ConeNormal => Map::new_2d(w, h, n, cone_normal::cone_normals(hm, edge)),
        MapKind::RelaxedConeNormal => Map::new_2d(w, h, n, cone_normal::relaxed_cone_normals(hm, edge)),
        MapKind::MultiCone => Map::new_2d(w, h, n, multi_cone::stacked_cone_normals(hm, edge, k)),
        MapKind::PiecewiseCone => Map::new_2d(w, h, n, multi_cone::piecewise_cone_normals(hm, edge, k)),
        MapKind::MaxMip => {
            let p = max_mip::cell_max_mip(hm, edge);
            let mut levels = p.levels.into_iter().map(|l| Map::new_2d(l.w, l.h, n, l.data));
            let mut base = levels.next().expect("a pyramid has level 0");
            base.mips = levels.collect();
            base
        }
        MapKind::DistanceField => {
            let d = params.z_resolution as usize;
            if !(1..=1024).contains(&d) {
                return Err(MapError::Params { kind, message: format!("z_resolution = {d}, expected 1..=1024") });
            }
            Map {
                width: w,
                height: h,
                depth: d,
                channels: n,
                data: distance_field::distance_field(hm, edge, d),
                mips: Vec::new(),
            }
        }
        MapKind::CellCone => cells(cell::cone::cell_cone(hm, edge)),
        MapKind::CellQuadCone => {
            let g = cell::CellGrid::new(w, h, edge);
            let texels = cell::cone::quadrant_texels(&cell::cone::cell_quad_cone(hm, edge), g.cw, g.ch, edge);
            Map::new_2d(2 * g.cw, 2 * g.ch, n, texels)
        }
        MapKind::CellRelaxedCone => cells(cell::relaxed_cone::cell_relaxed_cone(hm, edge)),
        MapKind::CellConeNormal => cells(cell::cone::cell_cone_normal(hm, edge)),
        MapKind::CellMultiCone => cells(cell::multi_cone::cell_multi_cone(hm, edge, k)),
        MapKind::CellPiecewiseCone => cells(cell::multi_cone::cell_piecewise_cone(hm, edge, k)),
        MapKind::CellPatch => cells(cell::patch::cell_patch(hm, edge)),
    };
    Ok(map)
}

/// Builds and encodes in one go (the form a GPU upload wants). Pyramid levels are encoded
/// too, in [`EncodedBundle::mips`].
pub fn build_encoded(
    hm: &HeightMap,
    kind: MapKind,
    params: &MapParams,
    edge: EdgeMode,
    enc: &Encoding,
) -> Result<EncodedBundle, MapError> {
    let map = build(hm, kind, params, edge)?;
    Ok(EncodedBundle::from_map(&map, kind, enc))
}

/// An encoded map with its encoded mip levels (if any).
#[derive(Clone, Debug, PartialEq)]
pub struct EncodedBundle {
    /// Level 0: the map itself, encoded.
    pub base: EncodedMap,
    /// The encoded [`Map::mips`], level 1 first; empty when the map has none.
    pub mips: Vec<EncodedMap>,
}

impl EncodedBundle {
    /// Encodes `map` and its mip levels with `enc`, each channel rounded in the safe
    /// direction for `kind` ([`kind_rounding`]).
    pub(crate) fn from_map(map: &Map, kind: MapKind, enc: &Encoding) -> EncodedBundle {
        let r = kind_rounding(map, kind);
        EncodedBundle {
            base: encode::encode_channels(map, enc, &r),
            mips: map.mips.iter().map(|m| encode::encode_channels(m, enc, &kind_rounding(m, kind))).collect(),
        }
    }
}

/// Per-channel rounding of a built map of `kind` (its channel count decides K).
pub fn kind_rounding(map: &Map, kind: MapKind) -> Vec<Rounding> {
    let mut r = vec![kind.rounding(); map.channels];
    if kind.is_cell() && map.channels > 0 {
        r[map.channels - 1] = Rounding::Up;
    }
    r
}

/// The maps' stored layout, in the on-disk cache's file names ([`CacheKey::file_stem`]):
/// raised whenever a kind's values or texel layout change. 2: `cell_quad_cone` as 2 × 2
/// texels of `[ratio, apex]` a cell (it was one texel of 5 channels).
const MAPS_LAYOUT: u32 = 2;

/// What identifies a built map.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub(crate) struct CacheKey {
    /// [`HeightMap::content_hash`].
    pub content: u64,
    /// The kind of map.
    pub kind: MapKind,
    /// Only the parameters the kind reads ([`MapParams::relevant`]).
    pub params: MapParams,
    /// The edge mode the map was built with.
    pub edge: EdgeMode,
    /// The storage encoding.
    pub encoding: Encoding,
}

impl CacheKey {
    /// The key of `kind` built from `hm`; hashes the whole height map and keeps only the
    /// parameters `kind` reads.
    pub(crate) fn new(
        hm: &HeightMap,
        kind: MapKind,
        params: &MapParams,
        edge: EdgeMode,
        encoding: &Encoding,
    ) -> CacheKey {
        CacheKey { content: hm.content_hash(), kind, params: params.relevant(kind), edge, encoding: *encoding }
    }

    /// A file name that identifies the key (for the on-disk cache), with the maps' layout
    /// ([`MAPS_LAYOUT`]), so that a map a former layout stored is built again, not read.
    pub(crate) fn file_stem(&self) -> String {
        let mut f = crate::heightmap::Fnv::new();
        f.write(format!("{:?}", (MAPS_LAYOUT, self.kind, self.params, self.edge, self.encoding)).as_bytes());
        format!("{:016x}-{}-{:016x}", self.content, self.kind.name(), f.finish())
    }
}

/// Builds every (height map, kind, parameters, edge mode, encoding) at most once.
///
/// In memory always; with [`MapCache::with_dir`] also on disk, one `.npy` per key holding the
/// f32 map before encoding (encoding is deterministic, so a disk hit gives the same codes).
/// `max_mip` is cheap and is not kept on disk.
#[derive(Default)]
pub struct MapCache {
    mem: Mutex<HashMap<CacheKey, Arc<EncodedBundle>>>,
    dir: Option<PathBuf>,
    builds: std::sync::atomic::AtomicUsize,
}

impl MapCache {
    /// An empty cache that keeps maps in memory only.
    pub fn new() -> MapCache {
        MapCache::default()
    }

    /// A cache that also keeps maps under `dir` (created if missing).
    pub fn with_dir(dir: impl AsRef<Path>) -> MapCache {
        MapCache { dir: Some(dir.as_ref().to_path_buf()), ..MapCache::default() }
    }

    /// How many maps this cache actually built (misses).
    pub fn builds(&self) -> usize {
        self.builds.load(std::sync::atomic::Ordering::Relaxed)
    }

    /// The map for the key, built on a miss.
    pub fn get(
        &self,
        hm: &HeightMap,
        kind: MapKind,
        params: &MapParams,
        edge: EdgeMode,
        enc: &Encoding,
    ) -> Result<Arc<EncodedBundle>, MapError> {
        let key = CacheKey::new(hm, kind, params, edge, enc);
        if let Some(hit) = self.mem.lock().unwrap().get(&key) {
            return Ok(hit.clone());
        }
        if let Some(b) = self.load_disk(&key) {
            let b = Arc::new(b);
            self.mem.lock().unwrap().insert(key, b.clone());
            return Ok(b);
        }
        let map = build(hm, kind, &key.params, edge)?;
        self.builds.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        self.store_disk(&key, &map);
        let bundle = Arc::new(EncodedBundle::from_map(&map, kind, enc));
        self.mem.lock().unwrap().insert(key, bundle.clone());
        Ok(bundle)
    }

    fn load_disk(&self, key: &CacheKey) -> Option<EncodedBundle> {
        if key.kind == MapKind::MaxMip {
            return None;
        }
        let path = self.dir.as_ref()?.join(format!("{}.npy", key.file_stem()));
        let bytes = crate::io::read_regular(&path).ok()?;
        let hdr = crate::io::npy::parse_npy_header(&bytes).ok()?;
        if hdr.item_size != 4 {
            return None;
        }
        let n: usize = hdr.shape.iter().product();
        let body = bytes.get(hdr.data_offset..hdr.data_offset + 4 * n)?;
        let data: Vec<f32> = body.chunks_exact(4).map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]])).collect();
        let (depth, h, w, c) = match key.kind {
            MapKind::DistanceField => (*hdr.shape.first()?, *hdr.shape.get(1)?, *hdr.shape.get(2)?, 1),
            _ => (1, *hdr.shape.first()?, *hdr.shape.get(1)?, *hdr.shape.get(2).unwrap_or(&1)),
        };
        if w * h * depth * c != n || c != key.kind.channels(&key.params) {
            return None;
        }
        let map = Map { width: w, height: h, depth, channels: c, data, mips: Vec::new() };
        Some(EncodedBundle::from_map(&map, key.kind, &key.encoding))
    }

    fn store_disk(&self, key: &CacheKey, map: &Map) {
        let Some(dir) = &self.dir else { return };
        if key.kind == MapKind::MaxMip || std::fs::create_dir_all(dir).is_err() {
            return;
        }
        let path = dir.join(format!("{}.npy", key.file_stem()));
        let mut shape = Vec::new();
        if map.depth > 1 || key.kind == MapKind::DistanceField {
            shape.push(map.depth);
        }
        shape.extend([map.height, map.width]);
        if map.channels > 1 || key.kind.reads_cones() || key.kind.per_cell() {
            shape.push(map.channels);
        }
        // A cache: a map that cannot be stored is built again next time.
        let _ = crate::io::write_atomic(&path, &crate::io::npy::npy_bytes(&shape, &map.data));
    }
}
