//! The recording's channels and the sets of them a run asks for.

use super::RecordError;
use super::visual::OUTLINES_TOPIC;

/// One stream of the recording (see the module's table).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Channel {
    /// `/scene/static` once and `/scene` at every sample (`foxglove.SceneUpdate`).
    Scene,
    /// `/tf` (`foxglove.FrameTransforms`).
    Transforms,
    /// `/rollers` (`foxglove.PointCloud`).
    Rollers,
    /// `/outlines/sprocketN` once (`foxglove.PointCloud`).
    Outlines,
    /// `/links` (`ChainLinkForces`).
    Links,
    /// `/contacts` (`ChainContactForces`).
    Contacts,
    /// `/sprockets` (`SprocketSignals`).
    Sprockets,
    /// `/segments` (`SegmentSignals`).
    Segments,
    /// `/guides` (`GuideSignals`).
    Guides,
    /// `/tensioners` (`TensionerSignals`).
    Tensioners,
}

impl Channel {
    /// Every channel, in the order they are registered in a file.
    pub const ALL: [Self; 10] = [
        Self::Scene,
        Self::Transforms,
        Self::Rollers,
        Self::Outlines,
        Self::Links,
        Self::Contacts,
        Self::Sprockets,
        Self::Segments,
        Self::Guides,
        Self::Tensioners,
    ];

    /// Name in `--record-channels`.
    pub fn name(self) -> &'static str {
        match self {
            Self::Scene => "scene",
            Self::Transforms => "transforms",
            Self::Rollers => "rollers",
            Self::Outlines => "outlines",
            Self::Links => "links",
            Self::Contacts => "contacts",
            Self::Sprockets => "sprockets",
            Self::Segments => "segments",
            Self::Guides => "guides",
            Self::Tensioners => "tensioners",
        }
    }

    /// Topic written at every sample ([`Channel::Outlines`]: the prefix of
    /// its per-sprocket topics, written once).
    pub fn topic(self) -> &'static str {
        match self {
            Self::Scene => "/scene",
            Self::Transforms => "/tf",
            Self::Rollers => "/rollers",
            Self::Outlines => OUTLINES_TOPIC,
            Self::Links => "/links",
            Self::Contacts => "/contacts",
            Self::Sprockets => "/sprockets",
            Self::Segments => "/segments",
            Self::Guides => "/guides",
            Self::Tensioners => "/tensioners",
        }
    }
}

/// Topic of the static scene, written once at the first sample.
pub(crate) const STATIC_SCENE_TOPIC: &str = "/scene/static";

bitflags::bitflags! {
    /// A set of channels, one flag per [`Channel`] (`Channels::from(c)`).
    #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
    pub struct Channels: u16 {
        /// [`Channel::Scene`].
        const SCENE = 1 << 0;
        /// [`Channel::Transforms`].
        const TRANSFORMS = 1 << 1;
        /// [`Channel::Rollers`].
        const ROLLERS = 1 << 2;
        /// [`Channel::Links`].
        const LINKS = 1 << 3;
        /// [`Channel::Contacts`].
        const CONTACTS = 1 << 4;
        /// [`Channel::Sprockets`].
        const SPROCKETS = 1 << 5;
        /// [`Channel::Segments`].
        const SEGMENTS = 1 << 6;
        /// [`Channel::Outlines`].
        const OUTLINES = 1 << 7;
        /// [`Channel::Guides`].
        const GUIDES = 1 << 8;
        /// [`Channel::Tensioners`].
        const TENSIONERS = 1 << 9;
    }
}

impl From<Channel> for Channels {
    fn from(c: Channel) -> Self {
        match c {
            Channel::Scene => Self::SCENE,
            Channel::Transforms => Self::TRANSFORMS,
            Channel::Rollers => Self::ROLLERS,
            Channel::Outlines => Self::OUTLINES,
            Channel::Links => Self::LINKS,
            Channel::Contacts => Self::CONTACTS,
            Channel::Sprockets => Self::SPROCKETS,
            Channel::Segments => Self::SEGMENTS,
            Channel::Guides => Self::GUIDES,
            Channel::Tensioners => Self::TENSIONERS,
        }
    }
}

impl Channels {
    /// Parses a comma-separated list of channel names (`all` for every
    /// channel), e.g. `scene,sprockets,segments`.
    pub fn parse(list: &str) -> Result<Self, RecordError> {
        let mut set = Self::empty();
        for name in list.split(',').map(str::trim).filter(|n| !n.is_empty()) {
            if name == "all" {
                set = Self::all();
                continue;
            }
            let c = Channel::ALL
                .iter()
                .find(|c| c.name() == name)
                .ok_or_else(|| RecordError::UnknownChannel(name.to_owned()))?;
            set |= Self::from(*c);
        }
        if set.is_empty() {
            return Err(RecordError::UnknownChannel(list.to_owned()));
        }
        Ok(set)
    }
}

impl Default for Channels {
    fn default() -> Self {
        Self::all()
    }
}
