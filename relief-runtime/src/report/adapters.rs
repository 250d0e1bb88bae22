//! One column set per adapter: each cell of the sweep with every adapter's frame time, its
//! frame time over the fastest pipeline's on the same scene and size on that adapter (so
//! that a ranking is judged on each adapter apart), and its RMS t error; and what
//! `relief report --add` added from browsers ([`super::add::log`]) and set aside.

use super::{data::short_scene, data::Data, text::fmt_ms, text::fmt_num, text::fmt_sci, text::TextTable, text::DASH};
use crate::results::Row;

/// The per-adapter table of `datas` (adapter, its rows), the first adapter's cells first;
/// `None` with fewer than two adapters and nothing added from a browser.
pub(crate) fn table(datas: &[(String, &Data)], added: &[super::add::Added]) -> Option<TextTable> {
    if datas.len() < 2 && added.is_empty() {
        return None;
    }
    let mut cells: Vec<(String, String, u32)> = Vec::new();
    for (_, d) in datas {
        for r in d.rows.iter().filter(|r| r.status.is_ok() && d.is_indexed(r)) {
            let k = (r.metrics.pipeline.to_string(), r.metrics.scene.clone(), r.metrics.size);
            if !cells.contains(&k) {
                cells.push(k);
            }
        }
    }
    // The fastest median frame time per adapter, scene and size.
    let fastest = |d: &Data, scene: &str, size: u32| {
        d.rows
            .iter()
            .filter(|r| r.status.is_ok() && r.metrics.scene == scene && r.metrics.size == size && d.is_indexed(r))
            .map(|r| r.metrics.frame_ms_median)
            .filter(|x| x.is_finite() && *x > 0.0)
            .fold(f64::INFINITY, f64::min)
    };
    let mut header = vec!["pipeline".to_string(), "scene".to_string(), "size".to_string()];
    for (a, _) in datas {
        header.push(format!("{a}: frame ms (median)"));
        header.push(format!("{a}: × fastest"));
        header.push(format!("{a}: ref_err_t_rms"));
    }
    let rows = cells
        .iter()
        .map(|(p, s, z)| {
            let mut row = vec![format!("`{p}`"), short_scene(s).to_string(), z.to_string()];
            for (_, d) in datas {
                match d.ok(p, s, *z) {
                    Some(r) => row.extend(columns(r, fastest(d, s, *z))),
                    None => row.extend([DASH.to_string(), DASH.to_string(), DASH.to_string()]),
                }
            }
            row
        })
        .collect();
    let mut notes = vec![format!(
        "Every ok cell on each of {} adapters, one column set per adapter: the median frame time, that time over the fastest \
         pipeline's on the same scene and size on the same adapter (rankings judged on each adapter apart; frame times on \
         different adapters do not compare), and the RMS t error. Rows added from a browser are scored by `relief report --add` \
         with the sweep's own scoring; their frame times are the browser's (timestamp queries or wall clock, as the adapter's \
         name says) and are not paired with a baseline.",
        datas.len()
    )];
    for a in added {
        let mut n = format!(
            "Added from `{}`: {} rows under `{}`{}",
            a.file,
            a.rows,
            a.adapter,
            if a.replaced > 0 { format!(", replacing {} earlier rows", a.replaced) } else { String::new() }
        );
        if a.set_aside.is_empty() {
            n.push_str("; nothing set aside.");
        } else {
            n.push_str(&format!("; set aside: {}.", a.set_aside.join("; ")));
        }
        notes.push(n);
    }
    Some(TextTable { title: "Per adapter: frame time and accuracy".into(), notes, header, rows })
}

fn columns(r: &Row, fastest: f64) -> [String; 3] {
    let m = &r.metrics;
    let ratio = if fastest.is_finite() { fmt_num(m.frame_ms_median / fastest, 2) } else { DASH.to_string() };
    [fmt_ms(m.frame_ms_median), ratio, fmt_sci(m.ref_err_t_rms)]
}
