//! Pipeline-level options: settings that belong to the whole pipeline rather than to one
//! slot, written after the slots (`linear(32)+binary(5)+lod=auto`, `lod: [zero, auto]` in a
//! grid, `lod: auto` in the macros).
//!
//! | option | values | default |
//! | --- | --- | --- |
//! | `lod` | `zero`, `auto`, `level(k)` with k in `0..=15` | `zero` |
//! | `silhouette` | `none`, `clip` | `none` |
//! | `curved` | `none`, `quadric`, `prism` | absent: the flat tile |
//!
//! `curved=` makes the composer write a *mesh module* instead of the flat tile's
//! ([`crate::compose::mesh`], docs/meshes-shaders.md). Unlike the other options its absence
//! is not one of its values: `curved=none` is the tangent-space march on a mesh, and a
//! pipeline without `curved=` is today's flat-tile module, so `curved=none` is printed.
//!
//! A value is written like a stage (a bare word, or `level(k)`), so a grid can list several
//! (`lod: [zero, auto, level(1..=3)]`). Defaults are left out of the canonical text.

use std::fmt;

use super::parse::{err, ParseError};
use super::resolve::{RawStage, RawValue};
use super::suggest::nearest;
use super::Slot;

/// The highest mip level `lod=level(k)` may name (a 65536² map has 17 levels; 16 levels,
/// 0..=15, cover every map relief loads).
pub const MAX_LOD_LEVEL: u8 = 15;

/// Which mip level of the height map (and of every map read at a level) the stages sample.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Lod {
    /// Level 0, the full-resolution map (what every pipeline did before the option).
    #[default]
    Zero,
    /// The level of the pixel's footprint on the reference plane, computed from the camera
    /// (the same in the fragment and the probe entries), rounded to a whole level.
    Auto,
    /// Mip level `k` for every sample.
    Level(u8),
}

impl fmt::Display for Lod {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Lod::Zero => f.write_str("zero"),
            Lod::Auto => f.write_str("auto"),
            Lod::Level(k) => write!(f, "level({k})"),
        }
    }
}

/// What the pipeline does where the ray leaves the surface's tile without a hit.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Silhouette {
    /// Nothing: the surface is an infinite tiling (or clamped) relief.
    #[default]
    None,
    /// The pixel is clipped (its behaviour is up to the composer).
    Clip,
}

impl fmt::Display for Silhouette {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Silhouette::None => "none",
            Silhouette::Clip => "clip",
        })
    }
}

/// How the pipeline runs on a curved mesh (`curved=`): which correction for the curvature
/// of the base surface the mesh module's fragment makes (docs/meshes-shaders.md).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Curved {
    /// The tangent-space march of the flat tile in the interpolated frame of each fragment:
    /// what engines ship, the baseline.
    None,
    /// The per-vertex quadric of Oliveira & Policarpo 2005: the ray's height above the
    /// curved reference surface, a ray that leaves the shell discarded (the silhouette).
    Quadric,
    /// Each triangle extruded into a prism as deep as the relief, the search from the
    /// prism face's entry point to the ray's exit from the prism.
    Prism,
}

impl Curved {
    /// Every value, in the order errors list them.
    pub const ALL: [Curved; 3] = [Curved::None, Curved::Quadric, Curved::Prism];
    /// The value's name in the text form.
    pub fn name(self) -> &'static str {
        match self {
            Curved::None => "none",
            Curved::Quadric => "quadric",
            Curved::Prism => "prism",
        }
    }
}

impl fmt::Display for Curved {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// The pipeline options by name.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum OptionKey {
    /// [`Lod`].
    Lod,
    /// [`Silhouette`].
    Silhouette,
    /// [`Curved`].
    Curved,
}

impl OptionKey {
    /// All options in the order the canonical text prints them.
    pub const ALL: [OptionKey; 3] = [OptionKey::Lod, OptionKey::Silhouette, OptionKey::Curved];
    /// The option's name in the text form.
    pub fn name(self) -> &'static str {
        match self {
            OptionKey::Lod => "lod",
            OptionKey::Silhouette => "silhouette",
            OptionKey::Curved => "curved",
        }
    }
    /// The values, as written in errors.
    fn values(self) -> Vec<String> {
        match self {
            OptionKey::Lod => vec!["zero".into(), "auto".into(), format!("level(0..={MAX_LOD_LEVEL})")],
            OptionKey::Silhouette => vec!["none".into(), "clip".into()],
            OptionKey::Curved => Curved::ALL.iter().map(|c| c.name().to_string()).collect(),
        }
    }
}

impl fmt::Display for OptionKey {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// What a `KEY=` (text) or `KEY:` (grid, macros) names: a slot or a pipeline option.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Key {
    /// One of the four slots.
    Slot(Slot),
    /// A pipeline option.
    Option(OptionKey),
}

/// The slot or option called `name`, or an error at `pos` that lists them and names the
/// nearest.
pub fn key_named(name: &str, pos: usize) -> Result<Key, ParseError> {
    if let Some(s) = Slot::ALL.iter().copied().find(|s| s.name() == name) {
        return Ok(Key::Slot(s));
    }
    if let Some(o) = OptionKey::ALL.iter().copied().find(|o| o.name() == name) {
        return Ok(Key::Option(o));
    }
    let names: Vec<String> =
        Slot::ALL.iter().map(|s| s.name()).chain(OptionKey::ALL.iter().map(|o| o.name())).map(str::to_string).collect();
    let mut e = err(pos, name, format!("unknown slot or option `{name}`"));
    e.suggestion = nearest(name, names.iter().map(String::as_str)).map(str::to_string);
    e.expected = names;
    Err(e)
}

/// One option value as resolved.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum OptionValue {
    /// A `lod` value.
    Lod(Lod),
    /// A `silhouette` value.
    Silhouette(Silhouette),
    /// A `curved` value.
    Curved(Curved),
}

fn unknown(key: OptionKey, raw: &RawStage, words: &[&str]) -> ParseError {
    let mut e = err(raw.pos, &raw.name, format!("unknown {key} value `{}`", raw.name));
    e.suggestion = nearest(&raw.name, words.iter().copied()).map(str::to_string);
    e.expected = key.values();
    e
}

fn no_args(key: OptionKey, raw: &RawStage) -> Result<(), ParseError> {
    match &raw.args {
        None => Ok(()),
        Some(_) => Err(err(raw.pos, &raw.name, format!("the {key} value `{}` takes no parameters", raw.name))),
    }
}

/// Checks one option value as written (a bare word or `level(k)`), with errors at the
/// positions in `raw` and "did you mean" from [`nearest`].
pub(crate) fn resolve_option(key: OptionKey, raw: &RawStage) -> Result<OptionValue, ParseError> {
    match key {
        OptionKey::Lod => {
            let lod = match raw.name.as_str() {
                "zero" => {
                    no_args(key, raw)?;
                    Lod::Zero
                }
                "auto" => {
                    no_args(key, raw)?;
                    Lod::Auto
                }
                "level" => {
                    let args = raw.args.as_deref().unwrap_or_default();
                    let [a] = args else {
                        return Err(err(
                            raw.pos,
                            &raw.name,
                            format!(
                                "`level` takes one parameter, the mip level: level(k) with k in 0..={MAX_LOD_LEVEL}"
                            ),
                        ));
                    };
                    if let Some((n, npos)) = &a.name {
                        if n != "k" {
                            let mut e = err(*npos, n, format!("`level` has no parameter `{n}`"));
                            e.expected = vec!["k".into()];
                            return Err(e);
                        }
                    }
                    match a.value {
                        RawValue::Int(k) if k <= u64::from(MAX_LOD_LEVEL) => Lod::Level(k as u8),
                        RawValue::Int(k) => {
                            return Err(err(
                                a.pos,
                                &a.text,
                                format!("mip level {k} is out of range: allowed 0..={MAX_LOD_LEVEL}"),
                            ))
                        }
                        RawValue::Stage(_) => {
                            return Err(err(a.pos, &a.text, "the mip level of `level` is a whole number"))
                        }
                    }
                }
                _ => return Err(unknown(key, raw, &["zero", "auto", "level"])),
            };
            Ok(OptionValue::Lod(lod))
        }
        OptionKey::Silhouette => {
            let s = match raw.name.as_str() {
                "none" => Silhouette::None,
                "clip" => Silhouette::Clip,
                _ => return Err(unknown(key, raw, &["none", "clip"])),
            };
            no_args(key, raw)?;
            Ok(OptionValue::Silhouette(s))
        }
        OptionKey::Curved => {
            let Some(c) = Curved::ALL.into_iter().find(|c| c.name() == raw.name) else {
                return Err(unknown(key, raw, &Curved::ALL.map(Curved::name)));
            };
            no_args(key, raw)?;
            Ok(OptionValue::Curved(c))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::{Grid, Pipeline};
    use super::*;

    #[test]
    fn options_parse_print_and_round_trip() {
        for (text, canonical, lod, sil) in [
            ("linear(32)+binary(5)+lod=auto", "linear(32)+binary(5)+lod=auto", Lod::Auto, Silhouette::None),
            ("linear(32)+lod=zero", "linear(32)", Lod::Zero, Silhouette::None),
            (
                "linear(32)+lod=level( 3 )+silhouette=clip",
                "linear(32)+lod=level(3)+silhouette=clip",
                Lod::Level(3),
                Silhouette::Clip,
            ),
            (
                "linear(32)+silhouette=clip+lod=level(k=15)",
                "linear(32)+lod=level(15)+silhouette=clip",
                Lod::Level(15),
                Silhouette::Clip,
            ),
            ("linear(32)+lod=level(0)", "linear(32)+lod=level(0)", Lod::Level(0), Silhouette::None),
            ("coarse=linear(32)+silhouette=none", "linear(32)", Lod::Zero, Silhouette::None),
        ] {
            let p: Pipeline = text.parse().unwrap();
            assert_eq!((p.lod, p.silhouette), (lod, sil), "{text}");
            assert_eq!(p.to_string(), canonical, "{text}");
            assert_eq!(canonical.parse::<Pipeline>().unwrap(), p, "{text}");
        }
        // curved=none is a value of its own (a mesh module), printed; absent is the flat tile.
        for (text, canonical, curved) in [
            ("linear(32)+curved=none", "linear(32)+curved=none", Some(Curved::None)),
            (
                "linear(32)+binary(5)+curved=quadric+lod=level(2)",
                "linear(32)+binary(5)+lod=level(2)+curved=quadric",
                Some(Curved::Quadric),
            ),
            ("coarse=csm(15)+curved=prism", "csm(15)+curved=prism", Some(Curved::Prism)),
            ("linear(32)", "linear(32)", None),
        ] {
            let p: Pipeline = text.parse().unwrap();
            assert_eq!(p.curved, curved, "{text}");
            assert_eq!(p.to_string(), canonical, "{text}");
            assert_eq!(canonical.parse::<Pipeline>().unwrap(), p, "{text}");
        }
        assert_ne!("linear+curved=none".parse::<Pipeline>().unwrap(), "linear".parse::<Pipeline>().unwrap());
        // level(0) and zero sample the same level but are different pipelines as written.
        assert_ne!("linear+lod=level(0)".parse::<Pipeline>().unwrap(), "linear".parse::<Pipeline>().unwrap());
    }

    #[test]
    fn option_errors_name_the_token_and_the_nearest() {
        for (text, pos, token, msg, suggestion) in [
            ("linear(32)+lod=autp", 15, "autp", "unknown lod value `autp`", Some("auto")),
            ("linear(32)+lod=levl(2)", 15, "levl", "unknown lod value", Some("level")),
            ("linear(32)+lod=level(16)", 21, "16", "out of range: allowed 0..=15", None),
            ("linear(32)+lod=level", 15, "level", "takes one parameter", None),
            ("linear(32)+lod=auto(2)", 15, "auto", "takes no parameters", None),
            ("linear(32)+silhouette=clp", 22, "clp", "unknown silhouette value", Some("clip")),
            ("linear(32)+lodd=auto", 11, "lodd", "unknown slot or option", Some("lod")),
            ("linear(32)+lod=auto+binary(5)", 20, "binary", "options come after the slots", None),
            ("linear(32)+lod=auto+lod=zero", 20, "lod", "given twice", None),
            ("linear(32)+curved=quadrc", 18, "quadrc", "unknown curved value `quadrc`", Some("quadric")),
            ("linear(32)+curved=prizm", 18, "prizm", "unknown curved value", Some("prism")),
            ("linear(32)+curved=prism(2)", 18, "prism", "takes no parameters", None),
            ("linear(32)+curve=prism", 11, "curve", "unknown slot or option", Some("curved")),
            ("linear(32)+curved=none+curved=prism", 23, "curved", "given twice", None),
        ] {
            let e = text.parse::<Pipeline>().unwrap_err();
            assert_eq!((e.pos, e.token.as_str()), (pos, token), "{text}: {e}");
            assert!(e.message.contains(msg), "{text}: {e}");
            assert_eq!(e.suggestion.as_deref(), suggestion, "{text}: {e}");
        }
    }

    #[test]
    fn grids_take_options_as_axes() {
        let g: Grid =
            "coarse: [linear(8), linear(16)]\nrefine: binary(5)\nlod: [zero, auto, level(1..=2)]".parse().unwrap();
        let texts: Vec<String> = g.iter().map(|p| p.to_string()).collect();
        assert_eq!(
            texts,
            [
                "linear(8)+binary(5)",
                "linear(8)+binary(5)+lod=auto",
                "linear(8)+binary(5)+lod=level(1)",
                "linear(8)+binary(5)+lod=level(2)",
                "linear(16)+binary(5)",
                "linear(16)+binary(5)+lod=auto",
                "linear(16)+binary(5)+lod=level(1)",
                "linear(16)+binary(5)+lod=level(2)",
            ]
        );
        let g: Grid = "coarse: linear, silhouette: [none, clip], lod: auto".parse().unwrap();
        let texts: Vec<String> = g.iter().map(|p| p.to_string()).collect();
        assert_eq!(texts, ["linear(32)+lod=auto", "linear(32)+lod=auto+silhouette=clip"]);
        let e = "coarse: linear\nlod: [zero, aut]".parse::<Grid>().unwrap_err();
        assert_eq!((e.line_column, e.token.as_str()), (Some((2, 13)), "aut"), "{e}");
        assert_eq!(e.suggestion.as_deref(), Some("auto"));
        let g: Grid = "coarse: linear(8)\ncurved: [none, prism]".parse().unwrap();
        let texts: Vec<String> = g.iter().map(|p| p.to_string()).collect();
        assert_eq!(texts, ["linear(8)+curved=none", "linear(8)+curved=prism"]);
        let e = "coarse: linear\ncurved: [none, quadrc]".parse::<Grid>().unwrap_err();
        assert_eq!(
            (e.line_column, e.token.as_str(), e.suggestion.as_deref()),
            (Some((2, 16)), "quadrc", Some("quadric"))
        );
        let e = "coarse: linear\nlod: auto\nlod: zero".parse::<Grid>().unwrap_err();
        assert!(e.message.contains("given twice"), "{e}");
    }
}
