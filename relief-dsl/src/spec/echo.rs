//! Input echoed in an error message, made safe for a one-line message: an error that quoted
//! a newline of its input raw would span two lines, and one that quoted a 100 KB argument
//! whole would be 100 KB long.

/// The longest echo of an input, in characters, before it is shortened.
pub const ECHO_MAX: usize = 80;

/// The longest whole error line, in characters, before [`one_line`] shortens it.
pub const LINE_MAX: usize = 2000;

/// `text` as an error message may quote it: control characters escaped (`\n`, `\t`,
/// `\u{1b}`), and at most [`ECHO_MAX`] characters, the middle replaced by `…`.
pub fn echo(text: &str) -> String {
    shorten(&escape_controls(text), ECHO_MAX)
}

/// A whole error message on one line: control characters escaped and at most [`LINE_MAX`]
/// characters (head and tail kept, `…` between). The last guard before a message is
/// printed, for messages that quote input their producer did not pass through [`echo`].
pub fn one_line(message: &str) -> String {
    shorten(&escape_controls(message), LINE_MAX)
}

fn escape_controls(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        if c.is_control() {
            out.extend(c.escape_default());
        } else {
            out.push(c);
        }
    }
    out
}

fn shorten(text: &str, max: usize) -> String {
    let n = text.chars().count();
    if n <= max {
        return text.to_string();
    }
    let head = (max - 1) / 2;
    let tail = max - 1 - head;
    let mut out: String = text.chars().take(head).collect();
    out.push('…');
    out.extend(text.chars().skip(n - tail));
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn controls_are_escaped_and_long_text_shortened() {
        assert_eq!(echo("linea\nr(10)"), "linea\\nr(10)");
        assert_eq!(echo("a\u{1b}[31mb\tc\r"), "a\\u{1b}[31mb\\tc\\r");
        let long = format!("linear({})", "1,".repeat(50_000));
        let e = echo(&long);
        assert_eq!(e.chars().count(), ECHO_MAX);
        assert!(e.starts_with("linear(1,1,") && e.contains('…') && e.ends_with("1,)"));
        assert_eq!(echo("linear(8)"), "linear(8)");
        let line = one_line(&format!("x\n{}", "é".repeat(5000)));
        assert_eq!(line.chars().count(), LINE_MAX);
        assert!(!line.contains('\n') && line.starts_with("x\\n"));
    }
}
