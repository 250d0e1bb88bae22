//! What a report run produced ([`ReportSummary`]), and the counts the page and `tables.md`
//! both state.

use std::path::PathBuf;

use super::conclusions::{Conclusion, Verdict};

/// What `write` produced.
#[derive(Clone, Debug, Default)]
pub struct ReportSummary {
    /// The sweep folder.
    pub dir: PathBuf,
    /// Rows read from `results.jsonl` (after dropping unreadable lines).
    pub rows: usize,
    /// Rows with status `ok`.
    pub ok: usize,
    /// Failed rows: (pipeline, scene, error).
    pub failed: Vec<(String, String, String)>,
    /// Lines of `results.jsonl` that could not be read, with the reason.
    pub bad_lines: Vec<String>,
    /// Every file written, `tables.md` and `index.html` first.
    pub files: Vec<PathBuf>,
    /// The dissertation's conclusions, checked.
    pub conclusions: Vec<Conclusion>,
    /// Problems that did not stop the report (an unreadable image, ...).
    pub warnings: Vec<String>,
    /// The result folders read (one, or several merged).
    pub sources: Vec<PathBuf>,
    /// The adapters of the rows, the one the tables show first.
    pub adapters: Vec<String>,
}

impl ReportSummary {
    /// The rows read, as the page and `tables.md` both state them: `N (K ok, F failed, U
    /// unreadable lines skipped)`, the last part only when there are such lines.
    pub(crate) fn rows_counted(&self) -> String {
        let skipped = if self.bad_lines.is_empty() {
            String::new()
        } else {
            format!(", {} unreadable lines skipped", self.bad_lines.len())
        };
        format!("{} ({} ok, {} failed{skipped})", self.rows, self.ok, self.failed.len())
    }

    /// How many conclusions hold / do not hold / were not measured / are not decided, by
    /// `mse_dissertation_mean`.
    pub fn verdict_counts(&self) -> (usize, usize, usize, usize) {
        let mut c = (0, 0, 0, 0);
        for k in &self.conclusions {
            match k.ours_mse {
                Verdict::Holds => c.0 += 1,
                Verdict::DoesNotHold => c.1 += 1,
                Verdict::NotMeasured => c.2 += 1,
                Verdict::NotDecided => c.3 += 1,
            }
        }
        c
    }
}
