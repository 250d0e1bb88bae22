//! The examples' bodies, run as tests (cargo builds the examples themselves with the tests).

#[path = "../examples/declare.rs"]
#[allow(dead_code)]
mod declare;
#[path = "../examples/generate.rs"]
#[allow(dead_code)]
mod generate;

#[test]
fn declare_prints_the_combinations() {
    let lines = declare::run();
    assert!(lines.iter().any(|l| l.contains("linear(15)+binary(6)+shadow=soft(30)")), "{lines:#?}");
    assert!(lines.iter().any(|l| l.contains("iterative_parallax(4)+shadow=hard(24)  (reads: normal)")), "{lines:#?}");
    assert!(
        lines.iter().any(|l| l.contains("a grid of 15 pipelines, from linear(8) to linear_dynamic(8, 32)+interval(3)")),
        "{lines:#?}"
    );
}

#[test]
fn generate_writes_five_files_per_pipeline() {
    let dir = std::env::temp_dir().join(format!("relief-example-generate-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let stems = generate::run(&dir).unwrap();
    assert_eq!(stems.len(), 3 * 3 * 2);
    assert!(stems.contains(&"linear_16__interval_4__shadow-soft_16".to_string()), "{stems:?}");
    let files = std::fs::read_dir(&dir).unwrap().count();
    assert_eq!(files, stems.len() * 5);
    for s in &stems {
        let wgsl = std::fs::read_to_string(dir.join(format!("{s}.wgsl"))).unwrap();
        assert!(wgsl.contains("fn fs_main("), "{s}");
        let spv = std::fs::read(dir.join(format!("{s}.spv"))).unwrap();
        assert_eq!(&spv[..4], &0x0723_0203u32.to_le_bytes(), "{s}");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[path = "../examples/sweep.rs"]
#[allow(dead_code)]
mod sweep;

#[test]
fn sweep_measures_the_grid_and_writes_the_report() {
    let dir = std::env::temp_dir().join(format!("relief-example-sweep-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let (cells, files) = sweep::run(&dir).unwrap();
    assert_eq!(cells, 4 * 2 * 2, "4 coarse × 2 refine × 2 scenes");
    assert!(files > 0);
    let rows = relief::runtime::results::read_for_append(&dir).unwrap();
    assert_eq!(rows.len(), cells);
    assert!(rows.iter().all(|r| r.status.is_ok() && r.metrics.frame_ms_median > 0.0));
    assert!(dir.join("index.html").exists());
    std::fs::remove_dir_all(&dir).unwrap();
}
