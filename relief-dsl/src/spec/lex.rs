//! The one lexer of the text forms: a pipeline text (`linear(10)+binary(5)`) and a grid text
//! (`coarse: [linear(5..=35 step 5)]`) are read into the same tokens. The form decides which
//! characters are tokens: `+` belongs to pipelines; `[ ] : ..= "…"` and `#` comments belong
//! to grids. Anything else is an error at its position, so a character that only the other
//! form knows is reported where it stands.

use super::parse::{err, ParseError, TextForm};

/// A token's kind and value.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum Tok {
    Ident(String),
    Int(u64),
    Str(String),
    Open,
    Close,
    LBracket,
    RBracket,
    Comma,
    Eq,
    Colon,
    Plus,
    RangeEq,
    End,
}

/// A token, where it starts (a character offset) and its text (the offending token in errors).
#[derive(Clone, Debug)]
pub(crate) struct Token {
    pub tok: Tok,
    pub pos: usize,
    pub text: String,
}

/// Splits `input` into tokens of `form`, ending with [`Tok::End`] at the input's length.
pub(crate) fn lex(input: &str, form: TextForm) -> Result<Vec<Token>, ParseError> {
    let grid = form == TextForm::Grid;
    let chars: Vec<char> = input.chars().collect();
    let word_char = |c: char| c.is_ascii_alphanumeric() || c == '_';
    let mut out = Vec::new();
    let mut i = 0;
    while i < chars.len() {
        let c = chars[i];
        let start = i;
        let single = |tok| Token { tok, pos: start, text: c.to_string() };
        match c {
            c if c.is_whitespace() => {}
            '#' if grid => {
                while i < chars.len() && chars[i] != '\n' {
                    i += 1;
                }
                continue;
            }
            '(' => out.push(single(Tok::Open)),
            ')' => out.push(single(Tok::Close)),
            ',' => out.push(single(Tok::Comma)),
            '=' => out.push(single(Tok::Eq)),
            '+' if !grid => out.push(single(Tok::Plus)),
            '[' if grid => out.push(single(Tok::LBracket)),
            ']' if grid => out.push(single(Tok::RBracket)),
            ':' if grid => out.push(single(Tok::Colon)),
            '.' if grid => {
                if chars.get(i + 1) == Some(&'.') && chars.get(i + 2) == Some(&'=') {
                    out.push(Token { tok: Tok::RangeEq, pos: start, text: "..=".into() });
                    i += 3;
                    continue;
                }
                let text: String = chars[i..(i + 2).min(chars.len())].iter().collect();
                return Err(err(start, &text, "ranges are inclusive and written `a..=b` or `a..=b step s`"));
            }
            '"' if grid => {
                i += 1;
                while i < chars.len() && chars[i] != '"' && chars[i] != '\n' {
                    i += 1;
                }
                if chars.get(i) != Some(&'"') {
                    return Err(err(start, "\"", "a string that is not closed on its line"));
                }
                let text: String = chars[start + 1..i].iter().collect();
                out.push(Token { tok: Tok::Str(text.clone()), pos: start, text: format!("\"{text}\"") });
            }
            c if c.is_ascii_digit() => {
                while i < chars.len() && word_char(chars[i]) {
                    i += 1;
                }
                let text: String = chars[start..i].iter().collect();
                let n = text
                    .parse::<u64>()
                    .map_err(|_| err(start, &text, "not a whole number (parameters are whole numbers or names)"))?;
                out.push(Token { tok: Tok::Int(n), pos: start, text });
                continue;
            }
            c if c.is_ascii_alphabetic() || c == '_' => {
                while i < chars.len() && word_char(chars[i]) {
                    i += 1;
                }
                let text: String = chars[start..i].iter().collect();
                out.push(Token { tok: Tok::Ident(text.clone()), pos: start, text });
                continue;
            }
            '-' => return Err(err(start, "-", "negative numbers are not allowed")),
            other => {
                let made_of = match form {
                    TextForm::Pipeline => "a pipeline is made of names, whole numbers, ( ) , = and +",
                    TextForm::Grid => "a grid is made of names, whole numbers, ( ) [ ] , = : ..= and # comments",
                };
                return Err(err(start, &other.to_string(), format!("unexpected character; {made_of}")));
            }
        }
        i += 1;
    }
    out.push(Token { tok: Tok::End, pos: chars.len(), text: String::new() });
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn kinds(input: &str, form: TextForm) -> Vec<Tok> {
        lex(input, form).unwrap().into_iter().map(|t| t.tok).collect()
    }

    #[test]
    fn each_form_has_its_own_punctuation() {
        assert_eq!(
            kinds("a(1)+b", TextForm::Pipeline),
            [Tok::Ident("a".into()), Tok::Open, Tok::Int(1), Tok::Close, Tok::Plus, Tok::Ident("b".into()), Tok::End]
        );
        assert_eq!(
            kinds("c: [1..=2] # x\n\"n\"", TextForm::Grid),
            [
                Tok::Ident("c".into()),
                Tok::Colon,
                Tok::LBracket,
                Tok::Int(1),
                Tok::RangeEq,
                Tok::Int(2),
                Tok::RBracket,
                Tok::Str("n".into()),
                Tok::End
            ]
        );
        // A grid's punctuation is an unexpected character in a pipeline, and `+` in a grid,
        // reported at the character (offsets count characters, not bytes).
        for (input, form, pos) in [
            ("a[", TextForm::Pipeline, 1),
            ("a#", TextForm::Pipeline, 1),
            ("x:1", TextForm::Pipeline, 1),
            ("\"é\"+", TextForm::Grid, 3),
        ] {
            let e = lex(input, form).unwrap_err();
            assert_eq!(e.pos, pos, "{input}");
            assert!(e.message.starts_with("unexpected character"), "{input}: {e}");
        }
    }

    #[test]
    fn numbers_are_whole_and_end_at_a_word_boundary() {
        assert_eq!(lex("10_0", TextForm::Pipeline).unwrap_err().token, "10_0");
        assert_eq!(lex("99999999999999999999", TextForm::Grid).unwrap_err().token, "99999999999999999999");
        assert_eq!(kinds("18446744073709551615", TextForm::Grid)[0], Tok::Int(u64::MAX));
    }
}
