//! The dissertation's grids (Burger 2018, Tables 4.1-4.15 and Figures 4.5, 4.7-4.11) as
//! grid files, in `relief-runtime/grids/`, embedded at build time.
//!
//! A grid file uses the grid form of `relief_grid!` (see `relief_dsl::spec::grid`); a file
//! may hold several such grids separated by a line `---`, and stands for their union (Table
//! 4.3, for instance, pairs a linear-only half with a linear + binary half). The first
//! comment line describes the grid.

use relief_dsl::spec::grid::MAX_CELLS;
use relief_dsl::spec::suggest::nearest;
use relief_dsl::spec::{Grid, ParseError};
use relief_dsl::Pipeline;

/// A named grid and the scenes it is measured on.
#[derive(Clone, Debug)]
pub struct NamedGrid {
    /// The grid's name, as rows record it: a built-in name (`t4.1`, `f4.5`, `dissertation`,
    /// `lod`) or a grid file's stem.
    pub name: String,
    /// The first comment line of its file.
    pub description: String,
    /// Its cells: pipelines with the scene each is measured on, in declaration order, each
    /// pair once.
    pub cells: Vec<(Pipeline, String)>,
}

const FILES: &[(&str, &str)] = &[
    ("t4.1", include_str!("../../grids/t4.1.grid")),
    ("t4.2", include_str!("../../grids/t4.2.grid")),
    ("t4.3", include_str!("../../grids/t4.3.grid")),
    ("t4.4", include_str!("../../grids/t4.4.grid")),
    ("t4.5", include_str!("../../grids/t4.5.grid")),
    ("t4.6", include_str!("../../grids/t4.6.grid")),
    ("t4.7", include_str!("../../grids/t4.7.grid")),
    ("t4.8", include_str!("../../grids/t4.8.grid")),
    ("t4.9", include_str!("../../grids/t4.9.grid")),
    ("t4.10", include_str!("../../grids/t4.10.grid")),
    ("t4.11", include_str!("../../grids/t4.11.grid")),
    ("t4.12", include_str!("../../grids/t4.12.grid")),
    ("t4.13", include_str!("../../grids/t4.13.grid")),
    ("t4.14", include_str!("../../grids/t4.14.grid")),
    ("t4.15", include_str!("../../grids/t4.15.grid")),
    ("f4.5", include_str!("../../grids/f4.5.grid")),
    ("f4.7", include_str!("../../grids/f4.7.grid")),
    ("f4.8", include_str!("../../grids/f4.8.grid")),
    ("f4.9", include_str!("../../grids/f4.9.grid")),
    ("f4.10", include_str!("../../grids/f4.10.grid")),
    ("f4.11", include_str!("../../grids/f4.11.grid")),
];

/// Grids of relief's own, beyond the dissertation's: listed after `dissertation` and not
/// part of it. `lod` repeats Tables 4.1, 4.2 and 4.7 (textbook CSM: the safe form reads
/// per-cell maps, which have no level) with `lod: [zero, auto]`.
/// `frontier` pits the family engines ship against the safe methods on real and procedural
/// maps at two views (see [`default_views`]), for the report's answer table.
const EXTRA_FILES: &[(&str, &str)] =
    &[("lod", include_str!("../../grids/lod.grid")), ("frontier", include_str!("../../grids/frontier.grid"))];

/// The dissertation's five scenes: Lion, Self-shadow and Collage as relief's procedural
/// stand-ins, Shapes and Rock Bump as the real maps `four` and `rocks` (see
/// `crate::scene::builtin`).
pub const FIVE_SCENES: [&str; 5] = ["lion", "self_shadow", "collage", "four", "rocks"];

/// The procedural stand-ins that real maps replaced in [`FIVE_SCENES`] (Shapes, Rock Bump),
/// measured next to them in the figures that name those scenes.
pub(crate) const REPLACED_STAND_INS: [&str; 2] = ["shapes", "rock_bump"];

/// The scenes a named grid is measured on unless `--scene` says otherwise: Lion, the main
/// test scene, except where the dissertation names others (then the real map where relief
/// has one, and the replaced stand-in next to it).
pub(crate) fn default_scenes(name: &str) -> Vec<String> {
    let f47: Vec<&str> = FIVE_SCENES.iter().chain(&REPLACED_STAND_INS).copied().collect();
    let v: &[&str] = match name {
        "f4.5" => &["rocks", "self_shadow", "rock_bump"],
        "f4.7" => &f47,
        // Lion as the tables have it, and the real maps that stand for Rock Bump and Shapes.
        "lod" | "frontier" | DISSERTATION_VIEW => &["lion", "rocks", "four"],
        _ => &["lion"],
    };
    v.iter().map(|s| s.to_string()).collect()
}

/// The views a built-in grid repeats each of its scenes at, as scene-argument suffixes
/// ([`crate::scene::file::split_view`]); `""` is the scene's own camera. `frontier`: the
/// scenes' own 45° (every built-in scene's camera) and 70° from the normal.
pub(crate) fn default_views(name: &str) -> &'static [&'static str] {
    match name {
        "frontier" => &["", "@angle=70"],
        DISSERTATION_VIEW => &["@view=dissertation"],
        _ => &[""],
    }
}

/// The grid that repeats some of the dissertation's tables at the dissertation's own view
/// ([`crate::scene::View::Dissertation`]: depth scale 0.05, 20° from the normal, 25° field
/// of view, `lod=auto`), on Lion and the two real maps.
pub(crate) const DISSERTATION_VIEW: &str = "dissertation-view";

/// The tables [`DISSERTATION_VIEW`] repeats: linear search (4.1), binary (4.2) and interval
/// refinement (4.4), linear against cone step mapping (4.7), cone against quad cone (4.8).
pub(crate) const DISSERTATION_VIEW_TABLES: [&str; 5] = ["t4.1", "t4.2", "t4.4", "t4.7", "t4.8"];

/// [`DISSERTATION_VIEW`]: the cells of [`DISSERTATION_VIEW_TABLES`], each (pipeline, scene)
/// once, every scene at the dissertation's view. The safe cone forms read per-cell maps,
/// which have no mip chain, so under the view's `lod=auto` they are left out (the textbook
/// forms, which the dissertation measured, stay).
fn dissertation_view(scenes: Option<&[String]>) -> NamedGrid {
    let scenes = scenes.map(|s| s.to_vec()).unwrap_or_else(|| default_scenes(DISSERTATION_VIEW));
    let mut cells: Vec<(Pipeline, String)> = Vec::new();
    for t in DISSERTATION_VIEW_TABLES {
        let text = FILES.iter().find(|(n, _)| *n == t).map(|(_, text)| *text).expect("a built-in table");
        let pipelines = parse_grid_file(text).unwrap_or_else(|e| panic!("built-in grid {t}: {e}"));
        for p in pipelines.into_iter().filter(|p| !reads_cell_maps(p)) {
            for s in &scenes {
                for v in default_views(DISSERTATION_VIEW) {
                    let c = (p.clone(), format!("{s}{v}"));
                    if !cells.contains(&c) {
                        cells.push(c);
                    }
                }
            }
        }
    }
    NamedGrid {
        name: DISSERTATION_VIEW.into(),
        description: "Tables 4.1, 4.2, 4.4, 4.7 and 4.8 at the dissertation's view (depth scale 0.05, 20°, 25° field of view, lod=auto)".into(),
        cells,
    }
}

/// Whether a pipeline's coarse search is a cone method in its safe form (per-cell maps).
fn reads_cell_maps(p: &Pipeline) -> bool {
    p.coarse.params.iter().any(|(k, v)| k == "form" && v.to_string() == "safe")
}

/// Parses a grid file's text: one or more grids separated by `---` lines, as their union.
pub fn parse_grid_file(text: &str) -> Result<Vec<Pipeline>, ParseError> {
    let mut out: Vec<Pipeline> = Vec::new();
    let mut seen = std::collections::HashSet::new();
    let mut line_offset = 0;
    let mut block = String::new();
    let mut blocks = Vec::new();
    for (i, line) in text.lines().enumerate() {
        if line.trim() == "---" {
            blocks.push((line_offset, std::mem::take(&mut block)));
            line_offset = i + 1;
        } else {
            block.push_str(line);
            block.push('\n');
        }
    }
    blocks.push((line_offset, block));
    for (offset, b) in blocks {
        let grid: Grid = b.parse().map_err(|mut e: ParseError| {
            if let Some((line, _)) = &mut e.line_column {
                *line = line.saturating_add(u32::try_from(offset).unwrap_or(u32::MAX));
            }
            e
        })?;
        for p in grid {
            if seen.insert(p.clone()) {
                out.push(p);
            }
        }
        if out.len() > MAX_CELLS {
            return Err(ParseError {
                pos: 0,
                line_column: Some((u32::try_from(offset + 1).unwrap_or(u32::MAX), 1)),
                token: String::new(),
                message: format!("the grid file has more than {MAX_CELLS} pipelines"),
                expected: vec![],
                suggestion: None,
            });
        }
    }
    Ok(out)
}

fn description(text: &str) -> String {
    text.lines().find_map(|l| l.trim().strip_prefix('#').map(|d| d.trim().to_string())).unwrap_or_default()
}

fn named(name: &str, text: &str, scenes: Option<&[String]>) -> NamedGrid {
    let pipelines = parse_grid_file(text).unwrap_or_else(|e| panic!("built-in grid {name}: {e}"));
    let scenes = scenes.map(|s| s.to_vec()).unwrap_or_else(|| default_scenes(name));
    let mut cells = Vec::new();
    for p in pipelines {
        for s in &scenes {
            for v in default_views(name) {
                cells.push((p.clone(), format!("{s}{v}")));
            }
        }
    }
    NamedGrid { name: name.to_string(), description: description(text), cells }
}

/// Every built-in grid of the dissertation, then `dissertation`: all of them, each
/// (pipeline, scene) once; then `dissertation-view` (`DISSERTATION_VIEW`) and relief's
/// own grids (`lod`, `frontier`).
pub fn builtin(scenes: Option<&[String]>) -> Vec<NamedGrid> {
    let mut all: Vec<NamedGrid> = FILES.iter().map(|(n, t)| named(n, t, scenes)).collect();
    let mut union: Vec<(Pipeline, String)> = Vec::new();
    for g in &all {
        for c in &g.cells {
            if !union.contains(c) {
                union.push(c.clone());
            }
        }
    }
    all.push(NamedGrid {
        name: "dissertation".into(),
        description: "every table and figure of Burger 2018 chapter 4, duplicate cells measured once".into(),
        cells: union,
    });
    all.push(dissertation_view(scenes));
    all.extend(EXTRA_FILES.iter().map(|(n, t)| named(n, t, scenes)));
    all
}

/// The names of the built-in grids.
pub fn names() -> Vec<&'static str> {
    FILES
        .iter()
        .map(|(n, _)| *n)
        .chain(["dissertation", DISSERTATION_VIEW])
        .chain(EXTRA_FILES.iter().map(|(n, _)| *n))
        .collect()
}

/// Why [`load`] found no grid.
#[derive(Debug, thiserror::Error)]
pub enum GridError {
    /// Neither a built-in grid's name nor an existing file.
    #[error("no grid `{arg}`: not a built-in grid ({}{near}) and no such file", names.join(", "))]
    Unknown {
        /// The argument as given.
        arg: String,
        /// The built-in grids ([`names`]).
        names: Vec<&'static str>,
        /// `; did you mean `NAME`?` for a likely typo, else empty.
        near: String,
    },
    /// The grid file cannot be read.
    #[error(transparent)]
    Read(crate::io::FileError),
    /// A line of the grid file does not parse.
    #[error("{}: {source}", path.display())]
    Parse {
        /// The grid file.
        path: std::path::PathBuf,
        /// The parser's error (with the line).
        #[source]
        source: Box<ParseError>,
    },
    /// The grid file's pipelines times the scenes make more than [`MAX_CELLS`] cells.
    #[error(
        "{}: {pipelines} pipelines on {scenes} scenes make more than {MAX_CELLS} cells; split the grid (sweep --shard K/N shares one out)",
        path.display()
    )]
    TooLarge {
        /// The grid file.
        path: std::path::PathBuf,
        /// Its pipelines.
        pipelines: usize,
        /// The scenes they run on.
        scenes: usize,
    },
}

/// A grid by built-in name, or from a grid file.
pub fn load(arg: &str, scenes: Option<&[String]>) -> Result<NamedGrid, GridError> {
    if let Some(g) = builtin(scenes).into_iter().find(|g| g.name == arg) {
        return Ok(g);
    }
    let path = std::path::Path::new(arg);
    if !path.exists() {
        let names = names();
        let near = nearest(arg, names.iter().copied()).map(|n| format!("; did you mean `{n}`?")).unwrap_or_default();
        return Err(GridError::Unknown { arg: arg.to_string(), names, near });
    }
    let text =
        crate::io::read_regular_to_string(path).map_err(|e| GridError::Read(crate::io::FileError::read(path, e)))?;
    let pipelines = parse_grid_file(&text)
        .map_err(|source| GridError::Parse { path: path.to_path_buf(), source: Box::new(source) })?;
    let scenes = scenes.map(|s| s.to_vec()).unwrap_or_else(|| vec!["lion".to_string()]);
    let name = path.file_stem().and_then(|s| s.to_str()).unwrap_or("grid").to_string();
    if pipelines.len().saturating_mul(scenes.len()) > MAX_CELLS {
        return Err(GridError::TooLarge { path: path.to_path_buf(), pipelines: pipelines.len(), scenes: scenes.len() });
    }
    let cells = pipelines.into_iter().flat_map(|p| scenes.iter().map(move |s| (p.clone(), s.clone()))).collect();
    Ok(NamedGrid { name, description: description(&text), cells })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_builtin_grid_parses_and_the_union_has_no_duplicates() {
        let all = builtin(None);
        assert_eq!(all.len(), FILES.len() + 2 + EXTRA_FILES.len());
        let diss = &all[FILES.len()];
        assert_eq!(diss.name, "dissertation");
        let sum: usize = all[..FILES.len()].iter().map(|g| g.cells.len()).sum();
        assert!(diss.cells.len() < sum, "duplicate cells are measured once");
        for (i, c) in diss.cells.iter().enumerate() {
            assert!(!diss.cells[..i].contains(c));
        }
        // Table 4.1 has the dissertation's 13 step counts.
        assert_eq!(all[0].cells.len(), 13);
        // Table 4.3 is the union of its two halves (7 + 7).
        assert_eq!(all[2].cells.len(), 14);
        // `lod` is Tables 4.1, 4.2 and 4.7 twice, on three scenes: 13 linear searches (4.2's
        // and 4.7's linear ones among them), 2 × 6 with binary, 10 csm in each of two forms,
        // each with lod zero and auto. None of its lod=auto cells is in the dissertation's union.
        let lod = all.iter().find(|g| g.name == "lod").unwrap();
        assert_eq!(lod.cells.len(), (13 + 12 + 20) * 2 * 3);
        assert!(diss.cells.iter().all(|(p, _)| p.lod == relief_dsl::spec::Lod::Zero));
    }

    #[test]
    fn frontier_is_the_engine_family_against_every_safe_method_at_two_views() {
        let all = builtin(None);
        let f = all.iter().find(|g| g.name == "frontier").unwrap();
        let pipelines: Vec<String> = f.cells.iter().map(|(p, _)| p.to_string()).fold(Vec::new(), |mut v, p| {
            if !v.contains(&p) {
                v.push(p);
            }
            v
        });
        // 6 layer counts × 3 refinements, 5 conservative cone methods × 4, sphere and maxmip
        // × 4, 2 relaxed cone methods × 4.
        assert_eq!(pipelines.len(), 18 + 20 + 8 + 8);
        assert_eq!(f.cells.len(), pipelines.len() * 3 * 2);
        for n in [8, 256] {
            for r in ["interval(1)", "binary(5)", "binary(8)"] {
                assert!(pipelines.contains(&format!("linear_dynamic(1, {n})+{r}")), "{n} {r}");
            }
        }
        for m in ["csm", "qcsm", "cns", "mcns", "pcns", "sphere", "maxmip", "rcs", "rcns"] {
            assert_eq!(pipelines.iter().filter(|p| p.starts_with(&format!("{m}("))).count(), 4, "{m}");
        }
        // Every cone method in the grid is in its safe form (the default).
        assert!(!pipelines.iter().any(|p| p.contains("textbook")));
        for s in ["lion", "rocks", "four"] {
            assert!(f.cells.iter().any(|(_, c)| c == s) && f.cells.iter().any(|(_, c)| *c == format!("{s}@angle=70")));
            // The scene's own view is the 45° the grid's description names.
            let sc = crate::scene::scene_from_arg(&crate::scene::scene_spec(s)).unwrap();
            assert_eq!(sc.camera.angle_deg, 45.0, "{s}");
        }
        // Not part of the dissertation's union.
        let diss = all.iter().find(|g| g.name == "dissertation").unwrap();
        assert!(!diss.cells.iter().any(|(_, s)| s.contains('@')));
    }

    #[test]
    fn dissertation_view_repeats_five_tables_at_the_dissertations_view() {
        let g = load(DISSERTATION_VIEW, None).unwrap();
        let mut pipelines: Vec<String> = Vec::new();
        for (p, _) in &g.cells {
            if !pipelines.contains(&p.to_string()) {
                pipelines.push(p.to_string());
            }
        }
        // Table 4.1's 13 linear searches (4.7's ten among them), 4.2's and 4.4's 2 × 6
        // refinements, 4.7's ten and 4.8's five more textbook csm, 4.8's five qcsm.
        assert_eq!(pipelines.len(), 13 + 12 + 12 + 10 + 5, "{pipelines:?}");
        assert_eq!(g.cells.len(), pipelines.len() * 3);
        let cones: Vec<&String> =
            pipelines.iter().filter(|p| p.starts_with("csm(") || p.starts_with("qcsm(")).collect();
        assert_eq!(cones.len(), 15);
        assert!(cones.iter().all(|p| p.contains("textbook")), "only textbook cone forms (lod=auto): {cones:?}");
        for s in ["lion", "rocks", "four"] {
            assert_eq!(g.cells.iter().filter(|(_, c)| *c == format!("{s}@view=dissertation")).count(), pipelines.len());
        }
        // The scene's lod applies: no cell names its own.
        assert!(g.cells.iter().all(|(p, _)| p.lod == relief_dsl::spec::Lod::Zero));
    }

    #[test]
    fn grid_file_errors_name_the_line_of_the_whole_file() {
        let e = parse_grid_file("coarse: linear(5)\n---\ncoarse: lnear(5)\n").unwrap_err();
        assert_eq!(e.line_column.map(|(line, _)| line), Some(3));
    }

    #[test]
    fn an_unknown_grid_suggests_only_a_near_name() {
        let e = load("t4.l", None).unwrap_err().to_string();
        assert!(e.contains("did you mean `t4.1`?"), "{e}");
        let e = load("/nonexistent/relief/sweep.grid", None).unwrap_err().to_string();
        assert!(e.contains("no such file") && !e.contains("did you mean"), "{e}");
    }
}
