//! Paired timing under load: the same cell measured twice against the sweep's baseline
//! (`relief_runtime::measure::measure_paired`), once on the machine as it is and once while
//! CPU hogs (`yes > /dev/null`, one per core) run beside it. Its frame times change; its
//! ratio to the baseline should not: the two ratios' 95 % intervals must overlap, and the
//! quotient of the two ratios must hold 1 in its interval. Run with `LP_NUM_THREADS=1`:
//!
//! ```sh
//! LP_NUM_THREADS=1 cargo bench -p relief-runtime --bench paired [-- PIPELINE SCENE SIZE PAIRS]
//! ```
//!
//! Defaults: `linear(10)+interval(3)` on `lion` at 256², 25 pairs. Prints both rows and
//! exits with status 1 when the ratios disagree (a benchmark, not a test: it times).

use std::process::{Child, Command, Stdio};

use relief_runtime::gpu::Gpu;
use relief_runtime::measure::{measure_paired, Prepared};
use relief_runtime::Ratio;
use relief_runtime::{scene_from_arg, scene_spec};

/// CPU hogs, one per core, killed (by their own handles) when dropped.
struct Hogs(Vec<Child>);

impl Hogs {
    fn start() -> Hogs {
        let n = std::thread::available_parallelism().map(|n| n.get()).unwrap_or(2);
        Hogs((0..n).map(|_| Command::new("yes").stdout(Stdio::null()).spawn().expect("cannot start `yes`")).collect())
    }
}

impl Drop for Hogs {
    fn drop(&mut self) {
        for c in &mut self.0 {
            let _ = c.kill();
            let _ = c.wait();
        }
    }
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).filter(|a| !a.starts_with("--")).collect();
    if std::env::args().any(|a| a == "--list") {
        println!("paired_under_load: benchmark");
        return;
    }
    let pipeline = args.first().map(String::as_str).unwrap_or("linear(10)+interval(3)");
    let scene = args.get(1).map(String::as_str).unwrap_or("lion");
    let size: u32 = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(256);
    let pairs: u32 = args.get(3).and_then(|s| s.parse().ok()).unwrap_or(25);
    let g = Gpu::new().unwrap_or_else(|e| panic!("{e}"));
    let scene = scene_from_arg(&scene_spec(scene)).unwrap_or_else(|e| panic!("{e:#}"));
    let mut prep = Prepared::new(&g, scene, size).unwrap_or_else(|e| panic!("{e:#}"));
    let p = pipeline.parse().unwrap_or_else(|e| panic!("{e}"));
    println!(
        "adapter: {} ({}); {pipeline} on {} at {size}², against {}",
        g.adapter,
        g.driver,
        prep.scene.name,
        relief_runtime::measure::BASELINE
    );
    let mut run = |label: &str| {
        let m = measure_paired(&g, &mut prep, &p, 3, pairs).unwrap_or_else(|e| panic!("{e:#}")).metrics;
        let r = Ratio::to_baseline(&m).expect("a paired measurement has a ratio");
        println!("{label:<11} mean frame {:.3} ms, frame_ratio_to_baseline {r}", m.frame_ms_mean);
        (r, m.frame_ms_mean)
    };
    let (idle, idle_ms) = run("as it is");
    let (busy, busy_ms) = {
        let _hogs = Hogs::start();
        std::thread::sleep(std::time::Duration::from_millis(200));
        run("beside hogs")
    };
    let q = busy.over(&idle);
    let overlap = idle.lo <= busy.hi && busy.lo <= idle.hi;
    println!("frame time beside the hogs ÷ as it is: {:.3}", busy_ms / idle_ms);
    println!("ratio beside the hogs ÷ ratio as it is: {q}");
    let agree = overlap && q.lo <= 1.0 && 1.0 <= q.hi;
    println!("the ratio columns agree within their intervals: {}", if agree { "yes" } else { "no" });
    if !agree {
        std::process::exit(1);
    }
}
