//! Typed choice parameters: a word of the text form and the value it stands for, and the
//! choices of the built-in cone methods. They live with the spec (the catalogue declares the
//! words, resolution checks them) and the stages match on the values.

/// A typed choice parameter: the words of the text form and the value each stands for. The
/// parameter ([`ParamDef::choice`](super::ParamDef::choice)) accepts exactly [`Choice::WORDS`], so a word that
/// resolution let through always converts ([`Args::choice`](super::Args::choice)), and a stage's `match` on the
/// value is exhaustive.
pub trait Choice: Copy + Sized + 'static {
    /// The words, the default first.
    const WORDS: &'static [&'static str];
    /// The value of `word`, `None` for a word not in [`Choice::WORDS`].
    fn from_word(word: &str) -> Option<Self>;
}

/// Implements [`Choice`] from one table of `word => value`.
macro_rules! choices {
    ($ty:ty { $($word:literal => $val:expr),+ $(,)? }) => {
        impl $crate::spec::Choice for $ty {
            const WORDS: &'static [&'static str] = &[$($word),+];
            fn from_word(word: &str) -> Option<Self> {
                match word {
                    $($word => Some($val),)+
                    _ => None,
                }
            }
        }
    };
}

/// `form=` of the cone methods: which cones a method steps on.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ConeForm {
    /// Cones of the bilinear cells: never past the first hit.
    Safe,
    /// The papers' cones of texel samples, stepping from the bilinear height as printed.
    Textbook,
}
choices!(ConeForm { "safe" => ConeForm::Safe, "textbook" => ConeForm::Textbook });

/// `sample=` of `csm` as written: `auto` is the form's own sampling.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SampleChoice {
    /// The form's own: the cell's cone (safe) or linear filtering (textbook).
    Auto,
    /// Linear filtering of the ratios (textbook only).
    Linear,
    /// The nearest texel's ratio (textbook only).
    Nearest,
    /// The smallest of the four texels' ratios (textbook only).
    Min4,
}
choices!(SampleChoice {
    "auto" => SampleChoice::Auto,
    "linear" => SampleChoice::Linear,
    "nearest" => SampleChoice::Nearest,
    "min4" => SampleChoice::Min4,
});

/// `start=` of `rcs` as written: `auto` is the form's own start.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StartChoice {
    /// The form's own: the bracket (safe) or the HK start (textbook).
    Auto,
    /// GPU Gems 3's start (textbook only).
    Hk,
    /// From the relaxed march's bracket.
    Bracket,
}
choices!(StartChoice { "auto" => StartChoice::Auto, "hk" => StartChoice::Hk, "bracket" => StartChoice::Bracket });

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_choice_word_has_a_value() {
        fn all<C: Choice>() -> bool {
            C::WORDS.iter().all(|w| C::from_word(w).is_some()) && C::from_word("sideways").is_none()
        }
        assert!(all::<ConeForm>() && all::<SampleChoice>() && all::<StartChoice>());
    }
}
