//! "Did you mean …?": the valid name nearest to a misspelt one. Stage, slot, parameter and
//! choice names (the text forms and the macros), scene names and grid names (relief-runtime)
//! all use this one rule.

/// The candidate nearest to `word` by Levenshtein distance (counted in characters), when it
/// is close enough to be a typo: at least one edit and at most half the longer name's length
/// (but always up to 2). On a tie the first candidate wins. `None` when nothing is that
/// close, or when `word` itself is a candidate.
///
/// ```
/// use relief_dsl::spec::suggest::nearest;
/// assert_eq!(nearest("lnear", ["none", "linear", "parallax"]), Some("linear"));
/// assert_eq!(nearest("xyzzy", ["none", "linear"]), None);
/// ```
pub fn nearest<'a>(word: &str, candidates: impl IntoIterator<Item = &'a str>) -> Option<&'a str> {
    let mut best: Option<(usize, &str)> = None;
    for c in candidates {
        let d = strsim::levenshtein(word, c);
        if d == 0 {
            return None;
        }
        if best.is_none_or(|(bd, _)| d < bd) {
            best = Some((d, c));
        }
    }
    let (d, c) = best?;
    let limit = (word.chars().count().max(c.chars().count()) / 2).max(2);
    (d <= limit).then_some(c)
}

#[cfg(test)]
mod tests {
    use super::nearest;

    /// Levenshtein distance by its definition: the fewest insertions, deletions and
    /// substitutions, by exhaustive recursion (inputs here are short).
    fn distance(a: &[char], b: &[char]) -> usize {
        match (a, b) {
            ([], _) => b.len(),
            (_, []) => a.len(),
            ([x, ra @ ..], [y, rb @ ..]) => {
                let sub = distance(ra, rb) + usize::from(x != y);
                sub.min(distance(ra, b) + 1).min(distance(a, rb) + 1)
            }
        }
    }

    #[test]
    fn picks_the_first_closest_within_the_limit() {
        let names = ["none", "binary", "interval", "secant", "rock_bump", "lion", "t4.1", "t4.2"];
        let words = ["lnear", "bianry", "binery", "intervl", "rockbump", "lino", "t41", "x", "secnt", "nne", "t4.3"];
        for w in words {
            let wc: Vec<char> = w.chars().collect();
            let ds: Vec<usize> = names.iter().map(|n| distance(&wc, &n.chars().collect::<Vec<_>>())).collect();
            let min = *ds.iter().min().unwrap();
            let first = names[ds.iter().position(|d| *d == min).unwrap()];
            let limit = (w.chars().count().max(first.chars().count()) / 2).max(2);
            let expected = (min > 0 && min <= limit).then_some(first);
            assert_eq!(nearest(w, names), expected, "{w}");
        }
        assert_eq!(nearest("lion", ["lion", "lino"]), None);
        assert_eq!(nearest("a", std::iter::empty()), None);
    }
}
