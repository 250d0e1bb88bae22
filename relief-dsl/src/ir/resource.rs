//! What each binding of a composed module holds: the table the builder writes as it declares
//! resources, and the runtime binds by.
//!
//! A resource is declared where a stage or an entry first reads it ([`super::ModuleCtx::bound`]),
//! and the builder records there what it is: the `Params` block, the height map read through
//! the nearest sampler, wall 2's cone map, the probe's rays. The composer hands the table out
//! with the module ([`crate::compose::Compiled::bindings`]), so that no reader has to work out
//! again from a binding number (or a global's name) what belongs there.

use crate::spec::MapReq;

/// How a stage samples a map: bilinear between texel centres, or the nearest texel.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Filter {
    /// Bilinear between texel centres.
    Linear,
    /// The nearest texel.
    Nearest,
}

/// An image a module reads: one of the scene's or a precomputed map.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Image {
    /// The height map.
    Height,
    /// The normal map.
    Normal,
    /// The albedo.
    Albedo,
    /// A room window's opacity map.
    Window,
    /// A precomputed map, with the parameters the stage read it with (never
    /// [`MapReq::Normal`], which is [`Image::Normal`]: [`Image::of`]).
    Map(MapReq),
}

impl Image {
    /// The image a stage reads as the map `req`: the scene's normal map for
    /// [`MapReq::Normal`] (one texture, whichever way it is asked for), else the map.
    pub fn of(req: MapReq) -> Image {
        match req {
            MapReq::Normal => Image::Normal,
            other => Image::Map(other),
        }
    }

    /// The texture's name in a plain module (`height_map`, `cone_map`, …).
    pub fn texture_name(self) -> String {
        match self {
            Image::Height => "height_map".into(),
            Image::Normal => "normal_map".into(),
            Image::Albedo => "albedo_map".into(),
            Image::Window => "window_map".into(),
            Image::Map(m) => m.texture_name(),
        }
    }

    /// The binding it has in a plain module, read through the linear sampler
    /// ([`crate::abi::binding`]; the nearest-filtered copy is at
    /// [`crate::abi::binding::NEAREST_OFFSET`] more).
    pub fn binding(self) -> u32 {
        use crate::abi::binding as b;
        match self {
            Image::Height => b::HEIGHT,
            Image::Normal => b::NORMAL,
            Image::Albedo => b::ALBEDO,
            Image::Window => b::ROOM_WINDOW,
            Image::Map(m) => m.binding(),
        }
    }
}

/// What one binding holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Resource {
    /// The `Params` uniform block ([`crate::abi::Params`]).
    Params,
    /// A room's uniform block (`RoomParams`).
    RoomParams,
    /// `image`, declared for reads through the sampler of `filter` (GLSL pairs a texture with
    /// one sampler, so an image read both ways is bound twice); `wall`: a room wall's own
    /// copy (its index), `None` in a plain module.
    Texture {
        /// The image.
        image: Image,
        /// The filter of the reads it was declared for.
        filter: Filter,
        /// The room wall whose image it is.
        wall: Option<u32>,
    },
    /// The sampler of a filter (the scene's edge mode as its address mode).
    Sampler(Filter),
    /// The probe's rays (storage, read).
    Rays,
    /// The probe's hits (storage, read and write).
    Hits,
    /// A mesh module's prism walk: its triangles' corners and neighbours (storage, read;
    /// `compose::mesh::PrismCell`).
    PrismCells,
}

/// One binding of a module (group 0).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct BindingEntry {
    /// The binding number.
    pub binding: u32,
    /// The global's name in the module.
    pub name: String,
    /// What is bound there.
    pub resource: Resource,
}

/// Every binding a module declares, in the order it declared them.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Bindings(Vec<BindingEntry>);

impl Bindings {
    /// The entry of binding `b`.
    pub fn get(&self, b: u32) -> Option<&BindingEntry> {
        self.0.iter().find(|e| e.binding == b)
    }

    /// The resource at binding `b`.
    pub fn resource(&self, b: u32) -> Option<Resource> {
        self.get(b).map(|e| e.resource)
    }

    /// Every entry, in declaration order.
    pub fn iter(&self) -> std::slice::Iter<'_, BindingEntry> {
        self.0.iter()
    }

    /// The number of bindings.
    pub fn len(&self) -> usize {
        self.0.len()
    }

    /// Whether the module binds nothing.
    pub fn is_empty(&self) -> bool {
        self.0.is_empty()
    }

    /// Records `entry`; a second resource at a binding already taken is the composer's error,
    /// named with both.
    pub(crate) fn push(&mut self, entry: BindingEntry) -> Result<(), String> {
        if let Some(old) = self.get(entry.binding) {
            return Err(format!(
                "binding {} is declared twice: `{}` ({:?}) and `{}` ({:?})",
                entry.binding, old.name, old.resource, entry.name, entry.resource
            ));
        }
        self.0.push(entry);
        Ok(())
    }
}

impl<'a> IntoIterator for &'a Bindings {
    type Item = &'a BindingEntry;
    type IntoIter = std::slice::Iter<'a, BindingEntry>;
    fn into_iter(self) -> Self::IntoIter {
        self.0.iter()
    }
}
