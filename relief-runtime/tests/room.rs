//! Rooms (Amaro & Gustafsson 2022): the dynamic layer count with the distance term, the wall selection
//! against an independent CPU ray–box intersection, per-wall hits of an exact pipeline
//! against the exact reference, the real-geometry baseline against the CPU reference, and
//! room files' errors and border warnings.

use std::path::Path;

use relief_dsl::ir::{Image, Resource};
use relief_dsl::spec::MapReq;
use relief_runtime::gpu::{self, Gpu, Program, SceneTextures};
use relief_runtime::room::accuracy::{reference_hits, room_accuracy};
use relief_runtime::room::gpu::{probe_room, RoomProgram, RoomTextures};
use relief_runtime::room::mesh::{render_geometry, wall_of_alpha, RoomMesh};
use relief_runtime::room::{
    border_warnings, builtin, file::load_room_file, room_from_arg, PixelRay, Room, RoomRay, NEAR_FAR, WALLS,
};
use relief_runtime::HeightMap;
use relief_runtime::Scene;

fn gpu() -> Gpu {
    Gpu::new().unwrap_or_else(|e| panic!("{e}"))
}

/// xorshift64*: reproducible pseudo-random numbers in [0, 1).
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        (self.0.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 11) as f64 / (1u64 << 53) as f64
    }
    fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.next()
    }
}

/// Amaro & Gustafsson 2022, §2.1.3, written out here: `L = (1 − cos θ)(L_min·d/(3+d) + L_max·(1 − d/(3+d))) + L_θmin·cos θ`.
fn paper_layers(cos: f64, d: f64, min: f64, max: f64, theta_min: f64) -> f64 {
    let w = d / (3.0 + d);
    (1.0 - cos) * (min * w + max * (1.0 - w)) + theta_min * cos
}

#[test]
fn linear_distance_takes_amaro_and_gustafssons_layer_count() {
    let g = gpu();
    // A flat map at height 0: no ray meets the surface before the bottom, so the linear
    // search runs every one of its layers and the probe's coarse count is the layer count.
    let mut scene = Scene::from_height_map("flat0", HeightMap::from_fn(16, 16, |_, _| 0.0));
    let (min, max, theta_min) = (16.0, 180.0, 4.0);
    let program = Program::new(&"linear_distance".parse().unwrap()).unwrap();
    let mut checked = 0;
    let mut counts = std::collections::BTreeSet::new();
    for (angle, distance) in [(10.0, 0.5), (45.0, 1.3), (70.0, 4.0), (80.0, 12.0)] {
        scene.camera.angle_deg = angle;
        scene.camera.distance = distance;
        let tex = SceneTextures::new(&g, &scene);
        let rays = scene.rays(24);
        let hits = gpu::probe(&g, &program, &scene, &tex, &rays).unwrap();
        let cam = scene.camera.camera_position();
        for (r, h) in rays.iter().zip(&hits) {
            let d = ((r.origin[0] - cam.x) as f64).hypot((r.origin[1] - cam.y) as f64).hypot(cam.z as f64);
            let vz = r.dir[2] as f64 * scene.depth_scale as f64;
            let cos = -vz / ((r.dir[0] as f64).powi(2) + (r.dir[1] as f64).powi(2) + vz * vz).sqrt();
            let l = paper_layers(cos, d, min, max, theta_min);
            if (l - l.round()).abs() < 1e-3 {
                continue; // f32 rounding may fall on either side of a whole number
            }
            let expected = l.floor().clamp(1.0, max) as u32;
            assert_eq!(h.coarse_steps, expected, "angle {angle}, distance {d:.3}, cos {cos:.4}: L = {l:.4}");
            counts.insert(expected);
            checked += 1;
        }
    }
    assert!(checked > 1000, "{checked} rays checked");
    assert!(counts.len() > 20, "the count varies with angle and distance: {counts:?}");
}

fn small_room() -> Room {
    builtin::room("default", Some(32)).unwrap()
}

/// The wall a ray from `o` along `w` (entering the box through the window) leaves the box
/// through: the slab method (Kay & Kajiya), the face of the smallest far-plane t. Returns the
/// wall, the exit point, and the gap to the second smallest far t (for skipping near-ties).
fn slab_exit(size: [f64; 3], o: [f64; 3], w: [f64; 3]) -> (usize, [f64; 3], f64) {
    let lo = [0.0, 0.0, -size[2]];
    let hi = [size[0], size[1], 0.0];
    let far: Vec<f64> = (0..3).map(|a| ((lo[a] - o[a]) / w[a]).max((hi[a] - o[a]) / w[a])).collect();
    let mut order = [0usize, 1, 2];
    order.sort_by(|&a, &b| far[a].total_cmp(&far[b]));
    let axis = order[0];
    let t = far[axis];
    let wall = match axis {
        0 if w[0] < 0.0 => 1, // left, x = 0
        0 => 2,               // right, x = W
        1 if w[1] < 0.0 => 3, // floor
        1 => 4,               // ceiling
        _ => 0,               // back
    };
    (wall, [o[0] + t * w[0], o[1] + t * w[1], o[2] + t * w[2]], far[order[1]] - t)
}

/// The exit point in the wall's texture coordinates, as the room format defines them (u, v
/// from 0 to 1 along each wall; see `relief_dsl::compose::interior::wall_frame`'s docs),
/// written out per wall.
fn wall_uv(size: [f64; 3], wall: usize, p: [f64; 3]) -> [f64; 2] {
    let [w, h, d] = size;
    match wall {
        0 => [p[0] / w, p[1] / h],
        1 => [-p[2] / d, p[1] / h],
        2 => [(p[2] + d) / d, p[1] / h],
        3 => [p[0] / w, -p[2] / d],
        _ => [p[0] / w, (p[2] + d) / d],
    }
}

#[test]
fn the_probe_selects_the_wall_a_cpu_ray_box_intersection_finds() {
    let g = gpu();
    let room = small_room();
    let size = room.size64();
    let mut rng = Rng(0x9E37_79B9_7F4A_7C15);
    let mut rays = Vec::new();
    let mut expected = Vec::new();
    while rays.len() < 20_000 {
        let o = [rng.range(-1.5, 3.5), rng.range(-1.0, 2.5), rng.range(0.2, 4.0)];
        let target = [rng.range(0.0, size[0]), rng.range(0.0, size[1]), 0.0];
        let w = [target[0] - o[0], target[1] - o[1], target[2] - o[2]];
        let ray = RoomRay {
            origin: [o[0] as f32, o[1] as f32, o[2] as f32, 0.0],
            dir: [w[0] as f32, w[1] as f32, w[2] as f32, 0.0],
        };
        // The f32 ray, widened, is the ray the probe traces.
        let o = [0, 1, 2].map(|i| ray.origin[i] as f64);
        let w = [0, 1, 2].map(|i| ray.dir[i] as f64);
        let (wall, p, gap) = slab_exit(size, o, w);
        if gap < 1e-4 {
            continue; // a ray through a room's edge: either wall is right within f32
        }
        rays.push(ray);
        expected.push((wall, wall_uv(size, wall, p)));
    }
    // With no coarse search the hit is where the ray meets the wall's plane (t = 0).
    let prog = RoomProgram::new(&"none".parse().unwrap()).unwrap();
    let tex = RoomTextures::new(&g, &room, &prog.maps).unwrap();
    let hits = probe_room(&g, &prog, &room, &tex, &rays).unwrap();
    let mut per_wall = [0usize; WALLS];
    for (i, (h, (wall, uv))) in hits.iter().zip(&expected).enumerate() {
        assert_eq!(h.wall as usize, *wall, "ray {i}: {:?}", rays[i]);
        per_wall[*wall] += 1;
        // f32 arithmetic on coordinates of a few units: errors ~1e-6; 1e-4 is the goal.
        assert!(
            (h.u as f64 - uv[0]).abs() < 1e-4 && (h.v as f64 - uv[1]).abs() < 1e-4,
            "ray {i}: uv ({}, {}) vs {uv:?}",
            h.u,
            h.v
        );
        assert_eq!(h.t, 0.0);
    }
    assert!(per_wall.iter().all(|&n| n > 500), "every wall is hit by many rays: {per_wall:?}");
}

#[test]
fn an_exact_pipeline_meets_every_wall_where_the_reference_does() {
    let g = gpu();
    let room = builtin::room("default", Some(64)).unwrap();
    let prog = RoomProgram::new(&"linear(400)+interval(8)".parse().unwrap()).unwrap();
    let tex = RoomTextures::new(&g, &room, &prog.maps).unwrap();
    let rays: Vec<PixelRay> = room.rays(128);
    let probe: Vec<RoomRay> = rays.iter().map(|r| r.ray).collect();
    let hits = probe_room(&g, &prog, &room, &tex, &probe).unwrap();
    let heights: Vec<Vec<f32>> = tex.walls.iter().map(|t| t.heights_on_device.clone()).collect();
    let refs = reference_hits(&room, &heights, &rays).unwrap();
    let acc = room_accuracy(&room, &heights, &rays, &hits, &refs);
    // Goal: on every wall, 99 % of the rays within 1e-4 of the exact t (400 linear steps are
    // finer than a texel of travel on all but the most grazing rays, and interval(8)
    // converges to f32 precision on a bilinear patch), none on another wall, none NaN.
    for (k, a) in acc.iter().enumerate() {
        eprintln!("{a:?}");
        assert!(a.rays > 500, "{}: {} rays", a.wall, a.rays);
        assert_eq!(a.wall_mismatch, 0, "{}", a.wall);
        let close = rays
            .iter()
            .zip(&hits)
            .zip(&refs)
            .filter(|((_, _), (w, _))| *w == k)
            .filter(|((_, h), (_, r))| r.is_some_and(|r| (h.t as f64 - r.t).abs() < 1e-4))
            .count();
        assert!(close as f64 >= 0.99 * a.rays as f64, "{}: {close} of {} rays within 1e-4", a.wall, a.rays);
        assert!(
            a.past_rate < 0.01 && a.skipped_rate < 0.01,
            "{}: past {}, skipped {}",
            a.wall,
            a.past_rate,
            a.skipped_rate
        );
    }
}

#[test]
fn the_geometry_baseline_shows_the_walls_and_depths_of_the_cpu_reference() {
    let g = gpu();
    let room = builtin::room("default", Some(64)).unwrap();
    let size = 128u32;
    let mesh = RoomMesh::new(&room, 128);
    let frames = render_geometry(&g, &room, &mesh, size, 0, 1).unwrap();
    let depth = frames.depth.unwrap();
    let heights: Vec<Vec<f32>> = room.walls.iter().map(|w| w.height.data.clone()).collect();
    let rays = room.rays(size);
    let refs = reference_hits(&room, &heights, &rays).unwrap();
    let (forward, _, _) = room.camera.basis();
    let cam = room.camera.position;
    let (near, far) = (NEAR_FAR.0 as f64, NEAR_FAR.1 as f64);
    let n = size as usize;
    let wall_at = |x: i64, y: i64| -> Option<usize> {
        if x < 0 || y < 0 || x >= n as i64 || y >= n as i64 {
            return None;
        }
        wall_of_alpha(frames.rgba[4 * (y as usize * n + x as usize) + 3])
    };
    let (mut id_ok, mut depth_ok, mut depth_n) = (0usize, 0usize, 0usize);
    let mut inside = vec![false; n * n];
    for (r, (wall, rf)) in rays.iter().zip(&refs) {
        inside[r.y as usize * n + r.x as usize] = true;
        let (x, y) = (r.x as i64, r.y as i64);
        // Silhouette: the reference's wall is drawn at this pixel or a neighbour.
        let near_ids: Vec<Option<usize>> =
            (-1..=1).flat_map(|dy| (-1..=1).map(move |dx| (dx, dy))).map(|(dx, dy)| wall_at(x + dx, y + dy)).collect();
        if near_ids.contains(&Some(*wall)) {
            id_ok += 1;
        }
        // Depth, away from silhouettes: the view depth of the reference's hit.
        if near_ids.iter().all(|w| *w == Some(*wall)) {
            let Some(rf) = rf else { continue };
            let wr = room.wall_ray(&r.ray);
            let p = room.wall_point(*wall, rf.u, rf.v, rf.z);
            let expect = (p - cam.as_dvec3()).dot(forward.as_dvec3());
            let ndc = depth[r.y as usize * n + r.x as usize] as f64;
            let got = far * near / (far - ndc * (far - near));
            depth_n += 1;
            // Goal: within a quarter of the wall's relief depth (the mesh interpolates the
            // bilinear surface linearly between grid points).
            if (got - expect).abs() <= 0.25 * room.walls[wr.wall].depth_scale as f64 {
                depth_ok += 1;
            }
        }
    }
    // Nothing but the facade outside the window.
    let outside_walls = (0..n * n).filter(|&i| !inside[i] && wall_of_alpha(frames.rgba[4 * i + 3]).is_some()).count();
    eprintln!(
        "walls within a pixel {id_ok}/{}, depth {depth_ok}/{depth_n}, walls outside the window {outside_walls}",
        rays.len()
    );
    // Goals: 99 % of the window's pixels show the reference's wall within a pixel; 95 % of
    // the pixels away from silhouettes have the reference's depth; at most one pixel row
    // or column of walls leaks past the window's edge.
    assert!(id_ok as f64 >= 0.99 * rays.len() as f64, "{id_ok} of {}", rays.len());
    assert!(depth_n > rays.len() / 2);
    assert!(depth_ok as f64 >= 0.95 * depth_n as f64, "{depth_ok} of {depth_n}");
    assert!(outside_walls <= 4 * n, "{outside_walls} wall pixels outside the window");
}

fn write(dir: &Path, name: &str, text: &str) -> std::path::PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

#[test]
fn bad_room_files_give_one_line_errors_naming_key_and_file() {
    let dir = std::env::temp_dir().join(format!("relief-room-files-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let cases: &[(&str, &str, &str)] = &[
        ("sise = [1, 1, 1]", "sise", "did you mean `size`"),
        ("size = [1, 1]", "size", "expected array of 3 numbers"),
        ("size = [1, -1, 1]", "size", "must be positive"),
        ("[walls.bak]\ndepth_scale = 0.1", "walls.bak", "did you mean `back`"),
        ("[walls.floor]\ndepth_scale = \"deep\"", "walls.floor.depth_scale", "expected number"),
        ("[walls.floor]\ndepth_scale = 0", "walls.floor.depth_scale", "positive"),
        ("[walls.left]\nheight_map = \"missing.png\"", "walls.left.height_map", "missing.png"),
        ("[walls.left]\nhieght_map = \"a.png\"", "walls.left.hieght_map", "did you mean `walls.left.height_map`"),
        ("[light]\npoint = [5, 5, 5]", "light.point", "inside the room"),
        ("[light]\npoint = [1, 1, -1]\ndirection = [0, 1, 0]", "light", "not both"),
        ("[camera]\nposition = [1, 1, -1]", "camera.position", "in front of the window"),
        ("map_size = 3", "map_size", "8..=4096"),
        ("[camera]\ntarget = [nan, 0.7, 2.0]", "camera.target", "must be three finite numbers"),
        ("[walls.floor]\ndepth_scale = 1e30", "walls.floor.depth_scale", "allowed 0 < depth scale <= 10"),
    ];
    for (i, (text, key, says)) in cases.iter().enumerate() {
        let p = write(&dir, &format!("bad{i}.toml"), text);
        let e = load_room_file(&p, None).expect_err(text).to_string();
        assert!(!e.contains('\n'), "one line: {e}");
        assert!(e.starts_with(&p.display().to_string()), "names the file: {e}");
        assert!(e.contains(&format!("key `{key}`")), "names `{key}`: {e}");
        assert!(e.contains(says), "says `{says}`: {e}");
    }
    let e = load_room_file(&dir.join("nope.toml"), None).unwrap_err().to_string();
    assert!(e.contains("nope.toml") && e.contains("not found"), "{e}");
    let p = write(&dir, "broken.toml", "size = [1, 1, 1\n");
    let e = load_room_file(&p, None).unwrap_err().to_string();
    assert!(!e.contains('\n') && e.contains("not valid TOML"), "{e}");
    // A good file: only what it names changes.
    let p =
        write(&dir, "good.toml", "size = [3, 2, 4]\n[light]\ndirection = [0, 1, 1]\n[walls.back]\ndepth_scale = 0.3\n");
    let r = load_room_file(&p, Some(16)).unwrap();
    assert_eq!(r.size, [3.0, 2.0, 4.0]);
    assert_eq!(r.walls[0].depth_scale, 0.3);
    assert_eq!(r.walls[1].depth_scale, builtin::room("default", Some(16)).unwrap().walls[1].depth_scale);
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn maps_not_at_height_1_on_their_border_are_warned_about() {
    // The procedural maps are at 1 on every border texel (checked here directly).
    for name in builtin::names() {
        let r = builtin::room(name, Some(40)).unwrap();
        for w in &r.walls {
            let m = &w.height;
            for y in 0..m.height {
                for x in 0..m.width {
                    if x == 0 || y == 0 || x + 1 == m.width || y + 1 == m.height {
                        assert_eq!(m.data[y * m.width + x], 1.0, "{name}: ({x}, {y})");
                    }
                }
            }
        }
        assert!(border_warnings(&r).is_empty());
    }
    // A given map with a low border: one warning, naming the wall, on stderr and returned.
    let dir = std::env::temp_dir().join(format!("relief-room-border-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let n = 16u32;
    let img = image::GrayImage::from_fn(n, n, |x, y| image::Luma([if x == 0 && y > 3 { 100 } else { 255 }]));
    img.save(dir.join("low.png")).unwrap();
    let p = write(&dir, "low.toml", "[walls.floor]\nheight_map = \"low.png\"\n");
    let (_, warnings) = room_from_arg(Some(p.to_str().unwrap()), Some(16)).unwrap();
    assert_eq!(warnings.len(), 1, "{warnings:?}");
    assert!(
        warnings[0].contains("floor") && warnings[0].contains(&format!("{} of its {}", n - 4, 4 * n - 4)),
        "{}",
        warnings[0]
    );
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn the_report_has_a_room_section_from_a_room_grid() {
    use relief_runtime::results::{Metrics, RoomCells, Row, Status};
    use relief_runtime::room::sweep::{read_rows, variants, GRID};
    let dir = std::env::temp_dir().join(format!("relief-room-report-{}", std::process::id()));
    std::fs::remove_dir_all(&dir).ok();
    std::fs::create_dir_all(&dir).unwrap();
    // Rows as `relief sweep --grid rooms` writes them (values made up: the section only
    // reports them); POM is 4× faster than geometry, effects add cost.
    let rows: Vec<Row> = variants()
        .iter()
        .enumerate()
        .map(|(i, v)| Row {
            grid: GRID.into(),
            metrics: Metrics {
                pipeline: v.pipeline.parse().unwrap(),
                scene: "room:default".into(),
                size: 64,
                frame_ms_median: 1.0 + i as f64,
                ..Default::default()
            },
            status: Status::Ok,
            room: Some(RoomCells {
                variant: v.label.into(),
                scatter: v.scatter.unwrap_or(0),
                wall_grid: 320,
                geometry_ms: 8.0,
                ..Default::default()
            }),
            ..Default::default()
        })
        .collect();
    for r in &rows {
        relief_runtime::results::append(&dir, r).unwrap();
    }
    assert_eq!(read_rows(&dir).unwrap(), rows);
    relief_runtime::report::write(&dir).unwrap();
    let md = std::fs::read_to_string(dir.join("tables.md")).unwrap();
    assert!(md.starts_with("# relief report: rooms\n"), "{md}");
    assert!(md.contains("Interior mapping in room:default"), "{md}");
    for v in variants() {
        assert!(md.contains(&format!("| {} |", v.label)), "{}: {md}", v.label);
    }
    // 8 ms of geometry against 2 ms of interior + POM: 4×, the paper's ordering.
    assert!(md.contains("4.00× the frame time of interior mapping + POM: the ordering holds"), "{md}");
    assert!(md.contains("rising, as in the paper"), "{md}");
    // Only the room section: the sections of sweep rows are left out of a rooms-only report.
    assert_eq!(md.matches("\n## ").count(), 1, "{md}");
    let html = std::fs::read_to_string(dir.join("index.html")).unwrap();
    assert!(html.contains("id=\"rooms\""));
    assert!(!html.contains("id=\"answer\"") && !dir.join("pareto.md").exists(), "{html}");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn relief_room_writes_both_renders_and_the_metrics() {
    let out = std::env::temp_dir().join(format!("relief-room-cli-{}", std::process::id()));
    let run = |args: &[&str]| std::process::Command::new(env!("CARGO_BIN_EXE_relief")).args(args).output().unwrap();
    let o = run(&[
        "room",
        "linear(16)+binary(3)+shadow=soft(8)",
        "--size",
        "48",
        "--grid",
        "24",
        "--map-size",
        "16",
        "--frames",
        "2",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    for f in ["frame.png", "baseline.png", "diff.png", "metrics.json"] {
        assert!(out.join(f).exists(), "{f}");
    }
    let m: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("metrics.json")).unwrap()).unwrap();
    let (f, b) = (m["frame_ms_median"].as_f64().unwrap(), m["baseline_ms_median"].as_f64().unwrap());
    assert!(f > 0.0 && b > 0.0);
    assert!((m["ratio_interior_to_baseline"].as_f64().unwrap() - f / b).abs() < 1e-9);
    assert_eq!(m["per_wall"].as_array().unwrap().len(), WALLS);
    assert_eq!(m["room"], "room:default");
    // A bad room: one line naming the file and the key.
    let bad = out.join("bad.toml");
    std::fs::write(&bad, "[walls.floor]\ndepth_scale = -1\n").unwrap();
    let o = run(&["room", "linear(8)", "--scene", bad.to_str().unwrap(), "--out", out.to_str().unwrap()]);
    assert!(!o.status.success());
    let e = String::from_utf8_lossy(&o.stderr);
    assert_eq!(e.trim().lines().count(), 1, "{e}");
    assert!(e.contains("bad.toml") && e.contains("key `walls.floor.depth_scale`"), "{e}");
    std::fs::remove_dir_all(&out).ok();
}

#[test]
fn a_safe_cone_pipeline_reads_each_walls_own_cone_map() {
    // Each wall's cone map is built from that wall's heights and bound at that wall's
    // binding: the safe form then never ends past the first hit (the safe methods' guarantee,
    // with its slack `metrics::PAST_SLACK`); a map of another wall could let it pass.
    let g = gpu();
    let room = builtin::room("default", Some(32)).unwrap();
    let prog = RoomProgram::new(&"csm(15)+binary(5)".parse().unwrap()).unwrap();
    // The binding table gives each wall its own cell cone map.
    let mut walls: Vec<u32> = prog
        .bindings
        .iter()
        .filter_map(|e| match e.resource {
            Resource::Texture { image: Image::Map(MapReq::CellCone), wall, .. } => wall,
            _ => None,
        })
        .collect();
    walls.sort();
    assert_eq!(walls, (0..WALLS as u32).collect::<Vec<_>>());
    let tex = RoomTextures::new(&g, &room, &prog.maps).unwrap();
    let rays = room.rays(64);
    let probe: Vec<RoomRay> = rays.iter().map(|r| r.ray).collect();
    let hits = probe_room(&g, &prog, &room, &tex, &probe).unwrap();
    let heights: Vec<Vec<f32>> = tex.walls.iter().map(|t| t.heights_on_device.clone()).collect();
    let refs = reference_hits(&room, &heights, &rays).unwrap();
    let past = hits
        .iter()
        .zip(&refs)
        .filter(|(h, (w, r))| {
            h.wall as usize != *w || r.is_none_or(|r| h.t as f64 > r.t + relief_runtime::metrics::PAST_SLACK)
        })
        .count();
    assert_eq!(past, 0, "{past} of {} rays past the first hit or on another wall", rays.len());
}

/// The room grid resumes: a second run over the same folder keeps the cells the first
/// measured (same rows, same frame times) and measures none.
#[test]
fn the_room_grid_resumes_where_it_stopped() {
    use relief_runtime::room::measure::RoomSetup;
    use relief_runtime::room::sweep;
    let dir = std::env::temp_dir().join(format!("relief-room-resume-{}", std::process::id()));
    std::fs::remove_dir_all(&dir).ok();
    let setup = RoomSetup { size: 24, grid: 16, warmup: 0, frames: 1 };
    let rooms = vec!["room:default".to_string()];
    // A plain sweep's row already in the folder: the room cells go beside it, and it stays.
    let plain = relief_runtime::Row {
        grid: "t4.1".into(),
        metrics: relief_runtime::Metrics {
            pipeline: "linear(8)".parse().unwrap(),
            scene: "scene:lion".into(),
            size: 24,
            ..Default::default()
        },
        ..Default::default()
    };
    std::fs::create_dir_all(&dir).unwrap();
    relief_runtime::results::append(&dir, &plain).unwrap();
    let first = sweep::run(&rooms, &setup, &dir).unwrap();
    assert_eq!((first.measured, first.skipped), (sweep::variants().len(), 0));
    assert!(first.rows.iter().all(|r| r.status.is_ok()), "{:?}", first.rows);
    // The rows round-trip through the typed reader: the plain row first, as it was, then each
    // room cell's row as the run returned it (compared as JSON, where NaN, a metric a room
    // cell does not measure, is null on both sides), its room columns set.
    let read = relief_runtime::results::read(&dir).unwrap();
    assert!(read.bad_lines.is_empty(), "{:?}", read.bad_lines);
    assert_eq!(read.rows.len(), 1 + first.rows.len());
    assert_eq!(read.rows[0], plain);
    let json = |r: &relief_runtime::Row| serde_json::to_string(r).unwrap();
    for (back, written) in read.rows[1..].iter().zip(&first.rows) {
        assert_eq!(json(back), json(written));
        let c = back.room.as_ref().unwrap();
        assert_eq!((back.grid.as_str(), c.wall_grid, c.per_wall.len()), (sweep::GRID, 16, WALLS));
        assert!(back.metrics.frame_ms_median > 0.0 && c.geometry_ms > 0.0, "{back:?}");
        assert!(back.metrics.ref_err_t_rms.is_finite() && back.metrics.avg_fetches.is_nan(), "{back:?}");
    }
    let again = sweep::run(&rooms, &setup, &dir).unwrap();
    assert_eq!((again.measured, again.skipped), (0, sweep::variants().len()));
    // The kept rows are the first run's (its frame times, which a re-measure would not repeat;
    // JSON keeps them to the digit).
    let key = |rows: &[relief_runtime::Row]| {
        rows.iter()
            .map(|r| {
                let c = r.room.as_ref().unwrap();
                (r.metrics.scene.clone(), c.variant.clone(), r.metrics.frame_ms_median, c.geometry_ms)
            })
            .collect::<Vec<_>>()
    };
    assert_eq!(key(&again.rows), key(&first.rows));
    // Another frame size is other cells.
    let bigger = sweep::run(&rooms, &RoomSetup { size: 32, ..setup }, &dir).unwrap();
    assert_eq!(bigger.measured, sweep::variants().len());
    assert_eq!(sweep::read_rows(&dir).unwrap().len(), 2 * sweep::variants().len());
    std::fs::remove_dir_all(&dir).ok();
}

/// Every wall flat at height 0.5: each wall ray `(origin, 1) + t·dir` (dir.z = −1) meets it
/// exactly at t = 1/2. A hit three texels of travel further (one texel: 1/(16·max(|dir.xy|,
/// 1)) on these 16² maps) is past the exact hit but skipped nothing (the ray stays below a
/// flat surface); a hit on another wall is both; the old `missed` names are `past`.
#[test]
fn a_room_hit_three_texels_past_a_flat_wall_is_past_but_not_skipped() {
    use relief_runtime::room::RoomHit;
    let mut room = builtin::room("default", Some(16)).unwrap();
    for w in &mut room.walls {
        w.height = HeightMap::from_fn(16, 16, |_, _| 0.5);
    }
    let heights: Vec<Vec<f32>> = room.walls.iter().map(|w| w.height.data.clone()).collect();
    let rays: Vec<PixelRay> = room.rays(24);
    let refs = reference_hits(&room, &heights, &rays).unwrap();
    let hit = |r: &PixelRay, wall: usize| {
        let wr = room.wall_ray(&r.ray);
        let texel = 1.0 / (16.0 * (wr.dir[0] * wr.dir[0] + wr.dir[1] * wr.dir[1]).sqrt().max(1.0));
        let t = 0.5 + 3.0 * texel;
        let [u, v] = [0, 1].map(|i| wr.origin[i] + t * wr.dir[i]);
        RoomHit {
            wall: wall as u32,
            t: t as f32,
            u: u as f32,
            v: v as f32,
            z: (1.0 - t) as f32,
            coarse_steps: 1,
            refine_steps: 0,
            converged: 1,
        }
    };
    for (_, rf) in &refs {
        assert!((rf.unwrap().t - 0.5).abs() < 1e-9, "the exact hit on a flat wall at 0.5: {rf:?}");
    }
    let hits: Vec<RoomHit> = rays.iter().zip(&refs).map(|(r, (k, _))| hit(r, *k)).collect();
    for a in room_accuracy(&room, &heights, &rays, &hits, &refs).iter().filter(|a| a.rays > 0) {
        assert_eq!((a.past, a.skipped, a.missed), (a.rays, 0, a.rays), "{a:?}");
        assert_eq!((a.past_rate, a.skipped_rate, a.missed_rate), (1.0, 0.0, 1.0), "{a:?}");
    }
    // The same hits reported on the next wall over: the shader chose another wall.
    let wrong: Vec<RoomHit> = rays.iter().zip(&refs).map(|(r, (k, _))| hit(r, (k + 1) % WALLS)).collect();
    for a in room_accuracy(&room, &heights, &rays, &wrong, &refs).iter().filter(|a| a.rays > 0) {
        assert_eq!((a.wall_mismatch, a.past, a.skipped), (a.rays, a.rays, a.rays), "{a:?}");
    }
}

/// A row written before `skipped_rate` and `past_rate` reads its `missed_rate` as
/// `past_rate` and has no `skipped_rate` (NaN, shown as a dash, never a 0).
#[test]
fn an_older_room_row_reads_missed_rate_as_past_rate() {
    use relief_runtime::room::sweep::{legacy_path, read_rows};
    let dir = std::env::temp_dir().join(format!("relief-room-old-row-{}", std::process::id()));
    std::fs::remove_dir_all(&dir).ok();
    std::fs::create_dir_all(&dir).unwrap();
    let line = r#"{"room":"room:default","variant":"+ POM","pipeline":"linear(8)","scatter":0,"size":64,"grid":320,"frame_ms":1.0,"baseline_ms":2.0,"ratio":0.5,"t_err_rms":0.01,"missed_rate":0.25,"mean_abs_diff":1.0,"status":"ok","error":"","per_wall":[{"wall":"back","rays":4,"t_err_rms":0.01,"missed_rate":0.5}]}"#;
    std::fs::write(legacy_path(&dir), format!("{line}\n")).unwrap();
    let rows = read_rows(&dir).unwrap();
    let (m, c) = (&rows[0].metrics, rows[0].room.as_ref().unwrap());
    assert_eq!((m.past_rate, c.per_wall[0].past_rate), (0.25, 0.5));
    assert!(m.skipped_rate.is_nan() && c.per_wall[0].skipped_rate.is_nan(), "{:?}", rows[0]);
    assert_eq!(
        (m.scene.as_str(), c.variant.as_str(), m.frame_ms_median, c.geometry_ms),
        ("room:default", "+ POM", 1.0, 2.0)
    );
    relief_runtime::report::write(&dir).unwrap();
    let md = std::fs::read_to_string(dir.join("tables.md")).unwrap();
    assert!(md.contains("| t err rms | skipped | past |"), "{md}");
    assert!(md.contains("| 1.000e-2 | — | 25.0% |"), "{md}");
    std::fs::remove_dir_all(&dir).ok();
}

/// The room tables as they were: `tests/data/rooms_before/` holds the rows an older relief's
/// `relief sweep --grid rooms --size 24 --frames 2` wrote (`rooms.jsonl`) and the `tables.md`
/// that relief's `relief report` wrote from them (before room rows were results rows). The
/// report of those rows read through the older shape, and again after the next room sweep
/// moved them into `results.jsonl` as typed rows (measuring nothing: every cell is kept),
/// writes that same `tables.md`, byte for byte.
#[test]
fn the_room_tables_of_an_older_folder_are_unchanged_before_and_after_its_rows_move() {
    use relief_runtime::room::measure::RoomSetup;
    use relief_runtime::room::sweep;
    let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/rooms_before");
    let want = std::fs::read_to_string(data.join("tables.md")).unwrap();
    let dir = std::env::temp_dir().join(format!("relief-room-before-{}", std::process::id()));
    std::fs::remove_dir_all(&dir).ok();
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::copy(data.join("rooms.jsonl"), sweep::legacy_path(&dir)).unwrap();
    relief_runtime::report::write(&dir).unwrap();
    assert_eq!(std::fs::read_to_string(dir.join("tables.md")).unwrap(), want);
    let rooms: Vec<String> = sweep::DEFAULT_ROOMS.iter().map(|r| r.to_string()).collect();
    let setup = RoomSetup { size: 24, grid: relief_runtime::room::mesh::DEFAULT_GRID, warmup: 0, frames: 1 };
    let moved = sweep::run(&rooms, &setup, &dir).unwrap();
    assert_eq!((moved.measured, moved.skipped, moved.rows.len()), (0, 8, 8));
    assert!(!sweep::legacy_path(&dir).exists());
    let read = relief_runtime::results::read(&dir).unwrap();
    assert_eq!((read.rows.len(), read.bad_lines.len()), (8, 0));
    assert!(read.rows.iter().all(|r| r.room.is_some() && r.grid == sweep::GRID));
    relief_runtime::report::write(&dir).unwrap();
    assert_eq!(std::fs::read_to_string(dir.join("tables.md")).unwrap(), want);
    std::fs::remove_dir_all(&dir).ok();
}
