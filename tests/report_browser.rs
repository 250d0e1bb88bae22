//! The report page of a small sweep in headless Chromium, as a reader meets it at 1400 px
//! wide (tests/browser/pages/report.html): no console error or failed request, the answer
//! table within the first 1000 px, sorting and filtering a table, every in-page link landing
//! on its target, pictures at least 256 px wide, nothing loaded from elsewhere.

#[path = "common/browser.rs"]
mod browser;

use std::time::Duration;

use browser::{run_page, Page};
use relief::runtime::sweep::{self, grids, NamedGrid};

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
    let opts = sweep::Options {
        grid,
        size: 64,
        frames: 2,
        warmup: 1,
        out: dir.clone(),
        progress: false,
        overrides: Default::default(),
        shard: None,
    };
    let s = sweep::run(&opts).expect("sweep");
    assert_eq!(s.failed, 0);
    relief::runtime::report::write(&dir).expect("report");

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
