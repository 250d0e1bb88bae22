//! Rank statistics for the report: Spearman's ρ and Kendall's τ-b.

/// Spearman rank correlation (average ranks for ties); None for fewer than 3 points or no
/// spread.
pub(crate) fn spearman(xs: &[f64], ys: &[f64]) -> Option<f64> {
    if xs.len() < 3 || xs.len() != ys.len() {
        return None;
    }
    let rx = ranks(xs);
    let ry = ranks(ys);
    pearson(&rx, &ry)
}

/// Ranks of `v`, 1-based, ties given their average rank.
fn ranks(v: &[f64]) -> Vec<f64> {
    let mut idx: Vec<usize> = (0..v.len()).collect();
    idx.sort_by(|&a, &b| v[a].total_cmp(&v[b]));
    let mut r = vec![0.0; v.len()];
    let mut i = 0;
    while i < idx.len() {
        let mut j = i;
        while j + 1 < idx.len() && v[idx[j + 1]] == v[idx[i]] {
            j += 1;
        }
        let avg = (i + j) as f64 / 2.0 + 1.0;
        for k in i..=j {
            r[idx[k]] = avg;
        }
        i = j + 1;
    }
    r
}

/// Pearson correlation; None without spread.
fn pearson(a: &[f64], b: &[f64]) -> Option<f64> {
    let n = a.len() as f64;
    let (ma, mb) = (a.iter().sum::<f64>() / n, b.iter().sum::<f64>() / n);
    let (mut sab, mut saa, mut sbb) = (0.0, 0.0, 0.0);
    for (x, y) in a.iter().zip(b) {
        sab += (x - ma) * (y - mb);
        saa += (x - ma) * (x - ma);
        sbb += (y - mb) * (y - mb);
    }
    (saa > 0.0 && sbb > 0.0).then(|| sab / (saa * sbb).sqrt())
}

/// Kendall's tau-b between two metrics over the same items; None without pairs.
pub(crate) fn kendall(a: &[f64], b: &[f64]) -> Option<(f64, usize)> {
    let (mut c, mut d, mut ta, mut tb) = (0i64, 0i64, 0i64, 0i64);
    let mut discordant = 0;
    for i in 0..a.len() {
        for j in i + 1..a.len() {
            let sa = (a[i] - a[j]).signum() * f64::from(a[i] != a[j]);
            let sb = (b[i] - b[j]).signum() * f64::from(b[i] != b[j]);
            if sa == 0.0 && sb == 0.0 {
                continue;
            } else if sa == 0.0 {
                ta += 1;
            } else if sb == 0.0 {
                tb += 1;
            } else if sa == sb {
                c += 1;
            } else {
                d += 1;
                discordant += 1;
            }
        }
    }
    let denom = (((c + d + ta) * (c + d + tb)) as f64).sqrt();
    (denom > 0.0).then(|| ((c - d) as f64 / denom, discordant))
}
