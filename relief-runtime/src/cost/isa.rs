//! Loops in a disassembly: what a loop body costs in the GPU's own instructions.
//!
//! RADV's assembly of an ACO shader is a list of instructions under block labels
//! (`BB12:`); branches name the label they jump to (`s_cbranch_scc1 BB12`). A loop is a
//! label that a branch *below* it jumps back to: its body is every instruction from the
//! label to the last such branch, both included, so a loop's body holds its nested loops
//! once each. Loops nest when one's range lies inside another's. Comments (after `;`),
//! blank lines and the label lines themselves are not instructions; the program's end
//! (`s_endpgm`) and what follows it (constant data, padding) are outside every loop.

/// One loop of a disassembly.
#[derive(Clone, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct IsaLoop {
    /// Instructions from the loop's label to its last branch back, both ends included
    /// (nested loops counted once).
    pub body: u32,
    /// 0 for a loop inside no other loop, 1 inside one, ….
    pub depth: u32,
    /// The instruction index (from 0) of the loop's first instruction.
    pub start: u32,
}

/// The instructions of a disassembly and its loops, in program order.
#[derive(Clone, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct IsaShape {
    /// Instruction lines up to and including `s_endpgm`.
    pub instructions: u32,
    /// Every loop, outer loops before the loops they hold, in order of their first
    /// instruction.
    pub loops: Vec<IsaLoop>,
}

impl IsaShape {
    /// The loops inside no other loop, in program order.
    pub fn top_level(&self) -> impl Iterator<Item = &IsaLoop> {
        self.loops.iter().filter(|l| l.depth == 0)
    }
}

/// A block label line: `BB12:` (the whole trimmed line).
fn label(line: &str) -> Option<&str> {
    let l = line.trim();
    let name = l.strip_suffix(':')?;
    (name.starts_with("BB") && name[2..].chars().all(|c| c.is_ascii_digit()) && name.len() > 2).then_some(name)
}

/// The label an instruction branches to, if it is a branch (`s_branch`, `s_cbranch_*`).
fn branch_target(code: &str) -> Option<&str> {
    let mut words = code.split_whitespace();
    let op = words.next()?;
    if op != "s_branch" && !op.starts_with("s_cbranch_") {
        return None;
    }
    words.next().map(|w| w.trim_end_matches(','))
}

/// Reads a disassembly's instructions and loops (see the module docs).
pub fn shape(disassembly: &str) -> IsaShape {
    let mut labels: std::collections::HashMap<&str, u32> = Default::default();
    let mut branches: Vec<(u32, &str)> = vec![];
    let mut n = 0u32;
    for line in disassembly.lines() {
        if let Some(name) = label(line) {
            labels.insert(name, n);
            continue;
        }
        let code = line.split(';').next().unwrap_or("").trim();
        if code.is_empty() {
            continue;
        }
        if let Some(t) = branch_target(code) {
            branches.push((n, t));
        }
        n += 1;
        if code.split_whitespace().next() == Some("s_endpgm") {
            break;
        }
    }
    // Per loop header, the last branch back to it.
    let mut ends: std::collections::BTreeMap<u32, u32> = Default::default();
    for (at, target) in branches {
        if let Some(&start) = labels.get(target) {
            if start <= at {
                let e = ends.entry(start).or_insert(at);
                *e = (*e).max(at);
            }
        }
    }
    let ranges: Vec<(u32, u32)> = ends.into_iter().collect();
    let loops = ranges
        .iter()
        .map(|&(s, e)| IsaLoop {
            body: e - s + 1,
            depth: ranges.iter().filter(|&&(s2, e2)| (s2, e2) != (s, e) && s2 <= s && e <= e2).count() as u32,
            start: s,
        })
        .collect();
    IsaShape { instructions: n, loops }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_loop_is_a_label_with_a_branch_back() {
        let text = "\
BB0:
  s_mov_b32 s0, 0 ; comment
  v_mov_b32 v0, 0
BB1:
  v_add_f32 v0, v0, v1
  s_add_u32 s0, s0, 1
  s_cmp_lt_u32 s0, 8
  s_cbranch_scc1 BB1
BB2:
  exp mrt0 v0, v0, v0, v0 done
  s_endpgm
  s_code_end
";
        let s = shape(text);
        assert_eq!(s.instructions, 8);
        assert_eq!(s.loops, vec![IsaLoop { body: 4, depth: 0, start: 2 }]);
    }

    #[test]
    fn nested_loops_and_a_forward_branch() {
        let text = "\
BB0:
  s_mov_b32 s0, 0
BB1:
  s_mov_b32 s1, 0
BB2:
  v_add_f32 v0, v0, v1
  s_cbranch_scc0 BB4
  s_cbranch_scc1 BB2
BB3:
  s_add_u32 s0, s0, 1
  s_cbranch_scc1 BB1
BB4:
  s_endpgm
";
        let s = shape(text);
        assert_eq!(s.instructions, 8);
        assert_eq!(s.loops, vec![IsaLoop { body: 6, depth: 0, start: 1 }, IsaLoop { body: 3, depth: 1, start: 2 }]);
        assert_eq!(s.top_level().count(), 1);
    }
}
