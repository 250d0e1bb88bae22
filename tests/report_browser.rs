//! The report page of a small sweep in headless Chromium, as a reader meets it at 1400 px
//! wide (tests/browser/pages/report.html): no console error or failed request, the answer
//! table within the first 1000 px, sorting and filtering a table, every in-page link landing
//! on its target, pictures at least 256 px wide, nothing loaded from elsewhere.

use crate::common::{browser, frames};

use std::time::Duration;

use browser::{run_page, Page};
use relief::runtime::sweep::{self, grids, NamedGrid};

/// Sweeps `grid` at `size`² into `dir` (two timed blocks a cell, no GPU compiler columns),
/// every cell measured, and writes its report.
fn sweep_and_report(dir: &std::path::Path, grid: NamedGrid, size: u32) {
    let opts = sweep::Options {
        grid,
        size,
        frames: 2,
        warmup: 1,
        out: dir.to_path_buf(),
        progress: false,
        overrides: Default::default(),
        shard: None,
        gpu_cost: None,
    };
    assert_eq!(sweep::run(&opts).expect("sweep").failed, 0);
    relief::runtime::report::write(dir).expect("report");
}

#[test]
fn the_report_page_answers_above_the_fold_and_its_tables_and_links_work() {
    let dir = std::env::temp_dir().join(format!("relief-report-page-{}", std::process::id()));
    std::fs::remove_dir_all(&dir).ok();
    // Table 4.1's rows on lion, and the engine family against a safe method on rocks at its
    // own view and at 70°.
    let lion = grids::parse_grid_file("coarse: linear([5, 10, 20])\n").unwrap();
    let rocks = grids::parse_grid_file(
        "coarse: linear_dynamic(1, [8, 32])\nrefine: [interval(1), binary(5)]\n---\ncoarse: csm([8, 32])\n",
    )
    .unwrap();
    let mut cells: Vec<_> = lion.into_iter().map(|p| (p, "lion".to_string())).collect();
    for s in ["rocks", "rocks@angle=70"] {
        cells.extend(rocks.iter().map(|p| (p.clone(), s.to_string())));
    }
    let grid = NamedGrid { name: "page".into(), description: "the report page test".into(), cells };
    sweep_and_report(&dir, grid, 64);

    let mut page = Page::new("pages/report.html");
    page.mounts.push(("sweep", &dir));
    page.size = (1400, 1000);
    page.timeout = Duration::from_secs(120);
    let r = run_page(&page);
    assert_eq!(r["ok"], true, "{r}");
    // lion, rocks and rocks at 70°.
    assert_eq!(r["answer"]["rows"], 3, "{r}");
    assert!(r["links"].as_u64().unwrap() >= 20, "{r}");
    assert!(r["shots"].as_u64().unwrap() >= 6, "{r}");
    std::fs::remove_dir_all(&dir).ok();
}

/// An 8-cell sweep (four pipelines on a real and a procedural height map at 64², one of them
/// `sphere(16)`, which reads the distance field the page computes) as the live section's
/// script draws it in Chromium (SwiftShader's WebGPU, pages/live.html): on the
/// real map `rocks` every pipeline at its measured view equals the sweep's own frame
/// (`relief render`'s renderer on lavapipe) within the goals, a mean absolute difference of
/// at most 1/255 and at most 1 % of pixels off by more than 8 in a channel. On the procedural
/// `lion` (one-texel walls) the same is measured and printed, not asserted: three of its four
/// pipelines miss the goals (two of the three without `sphere(16)`, measured with the runtime's
/// own Params block as well as the page's),
/// because SwiftShader's rasteriser shifts every pixel's ray by about 1/32 px and lion's
/// frames are the more sensitive to it (docs/browser.md). The page's Params for the measured
/// view are the runtime's.
///
/// The same page then runs the measure button's work (every cell timed and probed on
/// SwiftShader) and `report::add` scores its raw hits with the sweep's scoring: each cell's
/// RMS t error equals the native sweep's within 1e-4 (the issue's goal: the same WGSL on
/// the same rays and the same stored heights, so only the devices' filtering and float
/// rounding can differ), its frame times are positive, and the report has two adapters.
/// Adding the same adapter again is refused; with `replace` its rows are replaced.
#[test]
fn the_live_section_draws_and_measures_the_sweep_in_chromium() {
    let dir = std::env::temp_dir().join(format!("relief-live-page-{}", std::process::id()));
    std::fs::remove_dir_all(&dir).ok();
    let grid = grids::parse_grid_file(
        "coarse: [linear(16), csm(16)]\nrefine: binary(5)\n---\ncoarse: linear_dynamic(1, 32)\nrefine: interval(1)\n---\ncoarse: sphere(16)\nrefine: binary(5)\n",
    )
    .unwrap();
    let cells: Vec<_> =
        ["rocks", "lion"].iter().flat_map(|s| grid.iter().map(move |p| (p.clone(), s.to_string()))).collect();
    assert_eq!(cells.len(), 8);
    let grid = NamedGrid { name: "live".into(), description: "the live section test".into(), cells };
    sweep_and_report(&dir, grid, 64);

    let mut page = Page::new("pages/live.html");
    page.mounts.push(("sweep", &dir));
    page.timeout = Duration::from_secs(400);
    page.query.push(("measure", "1".into()));
    if std::env::var("RELIEF_LIVE_DUMP").is_ok() {
        page.query.push(("world", "1".into()));
    }
    // RELIEF_LIVE_RUST_PARAMS=1 draws with the runtime's Params block instead of the page's.
    if std::env::var("RELIEF_LIVE_RUST_PARAMS").is_ok() {
        page.query.push(("rust_params", "1".into()));
    }
    let r = run_page(&page);
    // The JavaScript camera gives the runtime's Params (f64 against f32: rounding only).
    assert!(r["params_diff"].as_f64().unwrap() < 1e-5, "{}", r["params_diff"]);
    if let Ok(d) = std::env::var("RELIEF_LIVE_DUMP") {
        std::fs::create_dir_all(&d).unwrap();
        for w in r["world"].as_array().into_iter().flatten() {
            let bytes = relief::runtime::io::base64::decode(w["rgba32f"].as_str().unwrap()).unwrap();
            std::fs::write(
                format!("{d}/world_{}_{}.bin", w["scene"].as_str().unwrap().replace(':', "_"), w["size"]),
                bytes,
            )
            .unwrap();
        }
    }
    let frames = r["frames"].as_array().unwrap();
    assert_eq!(frames.len(), 8, "{r}");
    for f in frames {
        let name = format!("{} on {}", f["pipeline"], f["scene"]);
        let got = relief::runtime::io::base64::decode(f["rgba"].as_str().unwrap()).unwrap();
        let want =
            image::open(dir.join(f["cell_dir"].as_str().unwrap()).join("frame.png")).unwrap().to_rgba8().into_raw();
        // RELIEF_LIVE_DUMP=DIR keeps both frames as PNG files for a look at where they differ.
        if let Ok(d) = std::env::var("RELIEF_LIVE_DUMP") {
            let stem =
                format!("{}_{}", f["scene"].as_str().unwrap().replace(':', "_"), f["pipeline"].as_str().unwrap());
            let stem: String = stem.chars().map(|c| if c.is_ascii_alphanumeric() { c } else { '_' }).collect();
            let side = (want.len() / 4).isqrt() as u32;
            std::fs::create_dir_all(&d).unwrap();
            image::save_buffer(format!("{d}/{stem}_browser.png"), &got, side, side, image::ColorType::Rgba8).unwrap();
            image::save_buffer(format!("{d}/{stem}_lavapipe.png"), &want, side, side, image::ColorType::Rgba8).unwrap();
        }
        let (mad, share) = frames::frame_difference(&got, &want);
        let mad = mad / 255.0;
        eprintln!(
            "{name}: mean |browser − lavapipe| {:.3}/255, {:.2} % of pixels off by more than 8",
            mad * 255.0,
            share * 100.0
        );
        if f["scene"] == "scene:rocks" {
            assert!(mad <= 1.0 / 255.0, "{name}: mean absolute difference {:.3}/255", mad * 255.0);
            assert!(share <= 0.01, "{name}: {:.2} % of pixels off by more than 8", share * 100.0);
        } else if mad > 1.0 / 255.0 || share > 0.01 {
            eprintln!(
                "{name}: misses the goals (mean absolute difference ≤ 1/255, ≤ 1 % of pixels off by more than 8)"
            );
        }
    }

    // The measure button's file, added to the sweep.
    let results = &r["results"];
    assert_eq!(results["format"], "relief-browser-results", "{}", results["format"]);
    let file = dir.join("browser-results.json");
    std::fs::write(&file, serde_json::to_vec(results).unwrap()).unwrap();
    let added = relief::runtime::report::add(&dir, std::slice::from_ref(&file), false).expect("add");
    assert_eq!(added.len(), 1);
    assert_eq!(added[0].rows, 8, "{:?}", added[0].set_aside);
    assert!(added[0].set_aside.is_empty(), "{:?}", added[0].set_aside);
    let adapter = added[0].adapter.clone();
    eprintln!("browser rows added under `{adapter}`");
    let rows = relief::runtime::results::read(&dir).unwrap().rows;
    assert_eq!(rows.len(), 16);
    eprintln!("| pipeline | scene | lavapipe frame ms | browser frame ms | lavapipe ref_err_t_rms | browser ref_err_t_rms | |Δ| |");
    for b in rows.iter().filter(|r| r.metrics.adapter == adapter) {
        let m = &b.metrics;
        let n = rows
            .iter()
            .find(|r| {
                r.metrics.adapter != adapter
                    && (&r.metrics.pipeline, &r.metrics.scene, r.metrics.size) == (&m.pipeline, &m.scene, m.size)
            })
            .expect("the native row");
        let d = (m.ref_err_t_rms - n.metrics.ref_err_t_rms).abs();
        eprintln!(
            "| {} | {} | {:.4} | {:.4} | {:.4e} | {:.4e} | {:.2e} |",
            m.pipeline,
            m.scene,
            n.metrics.frame_ms_median,
            m.frame_ms_median,
            n.metrics.ref_err_t_rms,
            m.ref_err_t_rms,
            d
        );
        assert!(
            d <= 1e-4,
            "{} on {}: RMS t error {} in the browser, {} native",
            m.pipeline,
            m.scene,
            m.ref_err_t_rms,
            n.metrics.ref_err_t_rms
        );
        assert!(m.frame_ms_median > 0.0 && m.frame_ms_p10 > 0.0, "{} on {}: frame times {m:?}", m.pipeline, m.scene);
        assert!(m.ref_err_t_rms.is_finite() && m.avg_fetches > 0.0, "{m:?}");
    }
    let report = relief::runtime::report::write(&dir).expect("report");
    assert_eq!(report.adapters.len(), 2, "{:?}", report.adapters);
    assert!(report.adapters.contains(&adapter), "{:?}", report.adapters);
    let tables = std::fs::read_to_string(dir.join("tables.md")).unwrap();
    assert!(tables.contains("Per adapter: frame time and accuracy"), "no per-adapter table");
    assert!(tables.contains(&format!("{adapter}: frame ms (median)")), "no column set for {adapter}");
    // Again: refused; with replace, the eight rows are replaced.
    let again = relief::runtime::report::add(&dir, std::slice::from_ref(&file), false).unwrap_err().to_string();
    assert!(again.contains("already holds 8 rows") && again.contains("--replace") && !again.contains('\n'), "{again}");
    let replaced = relief::runtime::report::add(&dir, std::slice::from_ref(&file), true).expect("replace");
    assert_eq!((replaced[0].rows, replaced[0].replaced), (8, 8));
    assert_eq!(relief::runtime::results::read(&dir).unwrap().rows.len(), 16);
    std::fs::remove_dir_all(&dir).ok();
}

/// `report::add` on files that are not a browser's results: each a one-line error naming
/// the problem; a well-formed row of a cell the sweep does not have is set aside and listed.
#[test]
fn adding_what_is_not_a_browser_results_file_is_a_one_line_error() {
    let dir = std::env::temp_dir().join(format!("relief-add-bad-{}", std::process::id()));
    std::fs::remove_dir_all(&dir).ok();
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("in.json");
    let add = |text: &str| {
        std::fs::write(&file, text).unwrap();
        relief::runtime::report::add(&dir, std::slice::from_ref(&file), false)
    };
    let cases = [
        ("pipeline,scene\nlinear(8),rocks\n", "is not a relief browser results file (not JSON"),
        (
            r#"{"format": "relief-results", "version": 1}"#,
            "its format is `relief-results`, expected `relief-browser-results`",
        ),
        (r#"[1, 2]"#, "it has no `format` field"),
        (
            r#"{"format": "relief-browser-results", "version": 2}"#,
            "relief-browser-results version 2, this relief reads version 1",
        ),
        (r#"{"format": "relief-browser-results", "version": 1, "adapter": "x"}"#, "not relief-browser-results rows"),
    ];
    for (text, want) in cases {
        let e = format!("{:#}", add(text).expect_err(text));
        assert!(e.contains(want), "{text}: {e}");
        assert!(!e.contains('\n'), "{text}: {e}");
    }
    let one = r#"{"format": "relief-browser-results", "version": 1, "relief_version": "0", "adapter": "Some GPU",
        "timer": "wall-clock", "rows": [{"pipeline": "linear(8)", "scene": "scene:rocks", "size": 64, "frame_ms": [1.0],
        "frames_per_block": 2, "probe_rays": 1, "probe_stride": 1, "hits_b64": ""}]}"#;
    let added = add(one).expect("a well-formed file");
    assert_eq!(added[0].rows, 0);
    assert_eq!(added[0].adapter, "Some GPU (WebGPU, wall-clock)");
    assert_eq!(added[0].set_aside, vec!["`linear(8)` on scene:rocks at 64²: not in the sweep".to_string()]);
    std::fs::remove_dir_all(&dir).ok();
}

/// FNV-1a, 32 bits: the hash `pages/data.html` computes of each inflated file.
fn fnv(bytes: &[u8]) -> u64 {
    let mut h: u32 = 0x811c_9dc5;
    for &b in bytes {
        h ^= u32::from(b);
        h = h.wrapping_mul(16_777_619);
    }
    u64::from(h)
}

/// The browser data as the page reads it equals the runtime's own bytes, texel for texel: a
/// 3-cell sweep whose pipelines read a cone map, the max-mip pyramid and the 3D distance
/// field, reported, and every data file loaded in headless Chromium through the live
/// section's loader (gzip inflated by the browser's `DecompressionStream`, byte planes put
/// back), each file's length and FNV-1a hash compared with those of the bytes the runtime
/// uploads, computed here from the scene (`gpu::scene_uploads`, `gpu::map_upload_of`,
/// `Scene::rays`) and the WGSL from `emit`, not from the files; and the probe rays, which are
/// not shipped but computed by the page (`probeRays`, from the f32 terms in the manifest),
/// equal to `Scene::rays` bit for bit at 32², 256² and 300² (there every second ray).
#[test]
fn the_page_inflates_the_browser_data_to_the_runtimes_bytes() {
    use relief::runtime::{gpu, scene_from_arg, MapKey, Program};
    let dir = std::env::temp_dir().join(format!("relief-data-page-{}", std::process::id()));
    std::fs::remove_dir_all(&dir).ok();
    let grid = grids::parse_grid_file("coarse: [csm(8), sphere(16)]\nrefine: none\n").unwrap();
    let cells: Vec<_> = grid.into_iter().map(|p| (p, "rocks".to_string())).collect();
    let grid = NamedGrid { name: "data".into(), description: "the browser data test".into(), cells };
    sweep_and_report(&dir, grid, 32);

    let mut page = Page::new("pages/data.html");
    page.mounts.push(("sweep", &dir));
    page.timeout = Duration::from_secs(120);
    let r = run_page(&page);
    assert_eq!(r["ok"], true, "{r}");

    let scene = scene_from_arg("scene:rocks").unwrap();
    let u = gpu::scene_uploads(&scene, true);
    let mut want: std::collections::BTreeMap<String, Vec<u8>> = std::collections::BTreeMap::new();
    want.insert("height".into(), u.height.levels.concat());
    want.insert("normal".into(), u.normal.levels.concat());
    want.insert("albedo".into(), u.albedo.levels.concat());
    // The probe rays, which the page computes: Scene::rays, every stride-th ray above 65 536
    // (300² has 90 000 pixels, most of which see the quad: stride 2).
    for size in [32u32, 256, 300] {
        let all = scene.rays(size);
        let stride = all.len().div_ceil(65_536).max(1);
        assert_eq!(stride, if size == 300 { 2 } else { 1 }, "{size}²: {} rays", all.len());
        let kept: Vec<_> = all.into_iter().step_by(stride).collect();
        want.insert(format!("probe:{size}"), bytemuck::cast_slice(&kept).to_vec());
    }
    for text in ["csm(8)", "sphere(16)", "maxmip(96)"] {
        let p: relief::Pipeline = text.parse().unwrap();
        want.insert(format!("wgsl:{p}"), relief::dsl::emit::emit(&p).unwrap().wgsl.into_bytes());
        for k in Program::new(&p).unwrap().maps.iter().filter_map(|m| MapKey::of(*m)) {
            let slug = format!("{}_{}_{}", k.kind.name(), k.params.cones, k.params.z_resolution);
            want.insert(format!("map:{slug}"), gpu::map_upload_of(&scene, k).unwrap().levels.concat());
        }
    }
    // Each file of the data once, and nothing else.
    let files = r["files"].as_array().unwrap();
    let mut got: Vec<String> = files.iter().map(|f| f["what"].as_str().unwrap().to_string()).collect();
    got.sort();
    assert_eq!(got, want.keys().cloned().collect::<Vec<_>>(), "{r}");
    assert!(want.keys().any(|k| k.starts_with("map:distance_field")), "{got:?}");
    for f in files {
        let what = f["what"].as_str().unwrap();
        let bytes = &want[what];
        assert_eq!(f["len"].as_u64(), Some(bytes.len() as u64), "{what}");
        assert_eq!(f["fnv"].as_u64(), Some(fnv(bytes)), "{what}: the page's bytes differ from the runtime's");
        // The distance field and the patch map are computed by the page, not shipped; every
        // other map is a file.
        let computed = ["distance_field", "cell_patch"].into_iter().find(|k| what.starts_with(&format!("map:{k}_")));
        assert_eq!(f["computed"].as_str(), computed, "{what}: {f}");
        if what.starts_with("map:") {
            assert_eq!(f["name"].is_null(), computed.is_some(), "{what}: {f}");
        }
        if computed.is_some() {
            eprintln!("the page computed {what} of rocks in {:.0} ms", f["ms"].as_f64().unwrap());
        }
    }
    assert!(want.keys().any(|k| k.starts_with("map:cell_patch")), "{got:?}");
    let shipped: Vec<String> = walk(&dir.join("browser")).iter().map(|p| p.display().to_string()).collect();
    assert!(shipped.iter().any(|p| p.contains("/map_")), "{shipped:?}");
    assert!(!shipped.iter().any(|p| p.contains("distance_field")), "a distance field was shipped: {shipped:?}");
    assert!(!shipped.iter().any(|p| p.contains("cell_patch")), "a patch map was shipped: {shipped:?}");
    std::fs::remove_dir_all(&dir).ok();
}

/// Every file under `dir`, recursively.
fn walk(dir: &std::path::Path) -> Vec<std::path::PathBuf> {
    let mut out = Vec::new();
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        if p.is_dir() {
            out.extend(walk(&p));
        } else {
            out.push(p);
        }
    }
    out
}

/// A height map of `w × h` with the features that make a distance field hard: one-texel
/// spikes to the top, one-texel walls (a row and a column, wrapping round with `Repeat`), a
/// one-texel pit, flat plateaus at heights that are no short binary fraction, and pseudo-random
/// low ground between them (a fixed linear congruential sequence, no crate).
fn spiky(w: usize, h: usize) -> relief::runtime::HeightMap {
    let mut state = 0x2545_f491_4f6c_dd1d_u64;
    let mut next = || {
        state = state.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
        (state >> 40) as f32 / (1u64 << 24) as f32
    };
    let mut data: Vec<f32> = (0..w * h).map(|_| 0.3 * next()).collect();
    for y in 0..h {
        for x in 0..w {
            let v = &mut data[y * w + x];
            if x == w / 3 || y == h - 1 {
                *v = 0.9; // walls, one texel thick; the row at the last y meets the first with Repeat
            } else if (x + 7 * y) % 13 == 0 {
                *v = 1.0; // spikes
            } else if x > 2 * w / 3 && y < h / 2 {
                *v = 0.1 + 0.6 / 7.0; // a plateau
            }
        }
    }
    data[(h / 2) * w + w / 2] = 0.0; // a pit
    relief::runtime::HeightMap::new(w, h, data)
}

/// The distance field the live section computes (`distanceField` in `web/live.js`, from the
/// heights) equals the runtime's generator (`maps::build` of `distance_field`) bit for bit: on
/// the real map `rocks` as its scene loads it (256², and two non-square crops of it), on the
/// procedural `lion` (one-texel edges and grooves, 256²) and on a map of one-texel spikes and
/// walls ([`spiky`], non-square), with both edge modes, at z resolutions 64 (the main job's
/// 256² × 64) and others. The page compares the values as bit patterns and reports the hash of
/// its bytes, checked here against the runtime's. The page's time at 256² × 64 is printed.
/// The same for the patch map (`cellPatch`, `maps::build` of `cell_patch`) on every one of
/// those maps and edge modes: its border strips under clamp, the wrap under repeat, a one-texel
/// wide map.
#[test]
fn the_page_computes_the_runtimes_distance_field_and_patch_map_bit_for_bit() {
    use relief::runtime::{maps, scene_from_arg, EdgeMode, HeightMap, MapKind, MapParams};
    let dir = std::env::temp_dir().join(format!("relief-field-page-{}", std::process::id()));
    std::fs::remove_dir_all(&dir).ok();
    std::fs::create_dir_all(&dir).unwrap();
    let rocks = scene_from_arg("scene:rocks").unwrap().height;
    let lion = scene_from_arg("scene:lion").unwrap().height;
    assert_eq!((rocks.width, rocks.height, lion.width, lion.height), (256, 256, 256, 256));
    let crop = |m: &HeightMap, x0: usize, y0: usize, w: usize, h: usize| {
        HeightMap::new(w, h, (0..h).flat_map(|y| (0..w).map(move |x| m.data[(y0 + y) * m.width + x0 + x])).collect())
    };
    let maps_of: Vec<(&str, HeightMap, u32)> = vec![
        ("rocks", rocks.clone(), 64),
        ("rocks 96x40", crop(&rocks, 17, 101, 96, 40), 64),
        ("rocks 33x70", crop(&rocks, 140, 3, 33, 70), 17),
        ("lion", lion, 64),
        ("spiky 50x23", spiky(50, 23), 64),
        ("spiky 1x9", spiky(1, 9), 5),
    ];
    let mut cases = Vec::new();
    let mut want_fnv = std::collections::BTreeMap::new();
    for (i, (name, hm, depth)) in maps_of.iter().enumerate() {
        std::fs::write(dir.join(format!("h{i}.bin")), bytemuck::cast_slice::<f32, u8>(&hm.data)).unwrap();
        for (edge, edge_name) in [(EdgeMode::Repeat, "repeat"), (EdgeMode::Clamp, "clamp")] {
            let params = MapParams { z_resolution: *depth, ..MapParams::default() };
            let field = maps::build(hm, MapKind::DistanceField, &params, edge).unwrap();
            assert_eq!(field.data.len(), hm.width * hm.height * *depth as usize);
            let bytes = bytemuck::cast_slice::<f32, u8>(&field.data);
            let case = format!("{name} {edge_name} z{depth}");
            std::fs::write(dir.join(format!("w{i}{edge_name}.bin")), bytes).unwrap();
            want_fnv.insert(case.clone(), fnv(bytes));
            cases.push(serde_json::json!({
                "name": case, "width": hm.width, "height": hm.height, "depth": depth, "edge": edge_name,
                "heights": format!("h{i}.bin"), "want": format!("w{i}{edge_name}.bin"),
            }));
            // The patch map the page computes for the safe csm, cns and csm_relax.
            let patch = maps::build(hm, MapKind::CellPatch, &MapParams::default(), edge).unwrap();
            let bytes = bytemuck::cast_slice::<f32, u8>(&patch.data);
            let case = format!("{name} {edge_name} cell_patch");
            std::fs::write(dir.join(format!("p{i}{edge_name}.bin")), bytes).unwrap();
            want_fnv.insert(case.clone(), fnv(bytes));
            cases.push(serde_json::json!({
                "name": case, "kind": "cell_patch", "width": hm.width, "height": hm.height, "edge": edge_name,
                "heights": format!("h{i}.bin"), "want": format!("p{i}{edge_name}.bin"),
            }));
        }
    }
    std::fs::write(dir.join("cases.json"), serde_json::to_vec(&cases).unwrap()).unwrap();

    let web = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("relief-runtime/web");
    let mut page = Page::new("pages/field.html");
    page.mounts.push(("web", &web));
    page.mounts.push(("cases", &dir));
    page.timeout = Duration::from_secs(300);
    let r = run_page(&page);
    assert_eq!(r["ok"], true, "{r}");
    let got = r["cases"].as_array().unwrap();
    assert_eq!(got.len(), want_fnv.len(), "{r}");
    for c in got {
        let name = c["name"].as_str().unwrap();
        eprintln!(
            "{name}: {} values, {} differ, {:.0} ms in the page",
            c["len"],
            c["differ"],
            c["ms"].as_f64().unwrap()
        );
        assert_eq!(c["len"], c["want_len"], "{name}");
        assert_eq!(c["differ"], 0, "{name}: the page's field differs from the runtime's, first at {}", c["first"]);
        assert_eq!(c["fnv"].as_u64(), Some(want_fnv[name]), "{name}: the page's bytes hash differently");
    }
    std::fs::remove_dir_all(&dir).ok();
}
