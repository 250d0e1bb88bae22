//! The dissertation's own numbers (Burger 2018, Tables 4.1–4.15), embedded from
//! `data/dissertation_tables.csv` (see `data/dissertation_tables.README.md`).

use relief_dsl::Pipeline;

use super::data::stage_steps;

const CSV: &str = include_str!("../../data/dissertation_tables.csv");

/// One printed configuration. Numbers are kept as printed; an empty field means the source
/// gives no value (and, for a method or step field, matches anything).
#[derive(Clone, Debug, Default)]
pub(crate) struct DissRow {
    pub table: String,
    pub coarse: String,
    pub coarse_steps: String,
    pub refine: String,
    pub refine_steps: String,
    pub shadow: String,
    pub shadow_steps: String,
    pub ao: String,
    pub avg_steps: String,
    pub mse: String,
    pub frame_ms: String,
    pub note: String,
}

impl DissRow {
    pub(crate) fn mse_f(&self) -> Option<f64> {
        self.mse.trim().parse().ok()
    }
    pub(crate) fn ms_f(&self) -> Option<f64> {
        self.frame_ms.trim().parse().ok()
    }

    /// Whether our pipeline is this configuration. The CSV's `soft_height` is our `soft`.
    pub(crate) fn matches(&self, p: &Pipeline) -> bool {
        fn name(d: &str, ours: &str) -> bool {
            let d = d.trim();
            d.is_empty() || d == ours || (d == "soft_height" && ours == "soft")
        }
        fn steps(d: &str, ours: u32) -> bool {
            let d = d.trim();
            d.is_empty() || d.parse::<u32>().ok() == Some(ours)
        }
        name(&self.coarse, &p.coarse.name)
            && steps(&self.coarse_steps, stage_steps(&p.coarse))
            && name(&self.refine, &p.refine.name)
            && steps(&self.refine_steps, stage_steps(&p.refine))
            && name(&self.shadow, &p.shadow.name)
            && steps(&self.shadow_steps, stage_steps(&p.shadow))
            && name(&self.ao, &p.ao.name)
    }
}

/// All printed rows, in the CSV's order.
pub(crate) struct Diss {
    pub rows: Vec<DissRow>,
}

impl Diss {
    pub(crate) fn load() -> Diss {
        Diss { rows: parse(CSV) }
    }

    /// The rows of table `table` (`4.1` …).
    pub(crate) fn table(&self, table: &str) -> Vec<&DissRow> {
        self.rows.iter().filter(|r| r.table == table).collect()
    }

    /// The first row of `table` that is `p`.
    pub(crate) fn find(&self, table: &str, p: &Pipeline) -> Option<&DissRow> {
        self.rows.iter().find(|r| r.table == table && r.matches(p))
    }
}

fn parse(text: &str) -> Vec<DissRow> {
    let mut rd = csv::ReaderBuilder::new().has_headers(true).flexible(true).from_reader(text.as_bytes());
    let mut out = Vec::new();
    for rec in rd.records().flatten() {
        let f = |i: usize| rec.get(i).unwrap_or("").trim().to_string();
        out.push(DissRow {
            table: f(0),
            coarse: f(1),
            coarse_steps: f(2),
            refine: f(3),
            refine_steps: f(4),
            shadow: f(5),
            shadow_steps: f(6),
            ao: f(7),
            avg_steps: f(8),
            mse: f(9),
            frame_ms: f(10),
            note: f(12),
        });
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_csv_has_every_row_and_matches_pipelines() {
        let d = Diss::load();
        assert_eq!(d.rows.len(), 201);
        let p: Pipeline = "linear(10)".parse().unwrap();
        assert_eq!(d.find("4.1", &p).unwrap().mse, "0.00515373");
        let p: Pipeline = "linear(20)+binary(4)+shadow=soft(30)".parse().unwrap();
        assert_eq!(d.find("4.14", &p).unwrap().frame_ms, "1.3812");
        let p: Pipeline = "linear(20)+binary(4)+shadow=hard(30)".parse().unwrap();
        assert_eq!(d.find("4.14", &p).unwrap().frame_ms, "1.3725");
        let p: Pipeline = "cns(15)+binary(5)+ao=cone_normal".parse().unwrap();
        assert_eq!(d.find("4.15", &p).unwrap().frame_ms, "0.9022");
    }
}
