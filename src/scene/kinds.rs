//! The scene's enumerations: contact law, pretension rule, wrap sense, a
//! sprocket's role, stepping and integrator.
//!
//! Each is named in one place, its variants: the name in scene files,
//! outputs and on the command line is the variant in `snake_case`, given by
//! serde (`rename_all`) and, with the `cli` feature, by clap (`ValueEnum`).
//! [`ALL`](ContactLaw::ALL), `name()` and `from_name()` are derived from the
//! serde form, so no list of names is written twice.
//!
//! The scene file keeps these fields as strings ([`super::SceneFile`]): an
//! unknown name is then one more field error with its path, reported with
//! every other problem, rather than a parse error that stops at the first.

use serde::{Deserialize, Serialize};

/// Defines a scene enumeration with its serde and clap names and the
/// `ALL` / `name` / `from_name` trio.
macro_rules! scene_enum {
    (
        $(#[$meta:meta])*
        pub enum $name:ident {
            $( $(#[$variant_meta:meta])* $variant:ident, )+
        }
    ) => {
        $(#[$meta])*
        #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
        #[serde(rename_all = "snake_case")]
        #[cfg_attr(feature = "cli", derive(clap::ValueEnum), value(rename_all = "snake_case"))]
        pub enum $name {
            $( $(#[$variant_meta])* $variant, )+
        }

        impl $name {
            /// Every variant, in the order error messages list them.
            pub const ALL: &'static [Self] = &[$(Self::$variant),+];

            /// The name used in scene files, outputs and on the command line.
            pub fn name(self) -> &'static str {
                variant_name(&self)
            }

            /// The variant of that name.
            pub fn from_name(name: &str) -> Option<Self> {
                Self::ALL.iter().copied().find(|v| v.name() == name)
            }
        }

        impl Named for $name {
            const ALL: &'static [Self] = $name::ALL;
            fn name(self) -> &'static str {
                $name::name(self)
            }
        }
    };
}

/// What the validator needs of a scene enumeration: its variants and names.
pub(crate) trait Named: Copy + 'static {
    /// Every variant, in the order error messages list them.
    const ALL: &'static [Self];
    /// The name in scene files.
    fn name(self) -> &'static str;
}

// Moved to `crate::geometry` separately; it keeps its own `name` and `parse`.
impl Named for super::ProfileKind {
    const ALL: &'static [Self] = &[Self::Circular, Self::Real];
    fn name(self) -> &'static str {
        super::ProfileKind::name(self)
    }
}

scene_enum! {
    /// Contact laws of the Hunt–Crossley family `K δⁿ (1 + χ δ̇/δ̇⁻)`
    /// (docs/model.md, “Laws of the family”).
    ///
    /// They differ only in the damping factor χ(e); the effective restitution of a
    /// single Hertzian impact under each law is tabled in `crate::forces`.
    pub enum ContactLaw {
        /// χ = 3(1 − e²)/4 (Lankarani & Nikravesh 1990), the paper's law.
        LankaraniNikravesh,
        /// χ = 3(1 − e)/2 (Hunt & Crossley 1975, with α = (1 − e)/δ̇⁻).
        HuntCrossley,
        /// χ = 8(1 − e)/(5e) (Flores et al. 2011); needs e > 0.
        Flores,
        /// χ = (1 − e²)/e (Gonthier et al. 2004); needs e > 0.
        Gonthier,
    }
}

impl ContactLaw {
    /// The damping factor χ of `K δⁿ (1 + χ δ̇/δ̇⁻)` for restitution `e`
    /// (infinite for Flores and Gonthier at e = 0, which the scene rejects).
    pub fn chi(self, e: f64) -> f64 {
        match self {
            Self::LankaraniNikravesh => 0.75 * (1.0 - e * e),
            Self::HuntCrossley => 1.5 * (1.0 - e),
            Self::Flores => 1.6 * (1.0 - e) / e,
            Self::Gonthier => (1.0 - e * e) / e,
        }
    }

    /// Whether χ(e) is finite only for e > 0.
    pub fn needs_positive_restitution(self) -> bool {
        matches!(self, Self::Flores | Self::Gonthier)
    }
}

scene_enum! {
    /// How the chain reaches its pretension (docs/model.md, “Pretension and static equilibrium”).
    pub enum PretensionRule {
        /// Keep every position and shorten the links' rest length.
        RestLength,
        /// Move the tensioner sprocket along its adjustment direction.
        Tensioner,
        /// Keep the links' rest length at the pitch: the tensioners' preloads
        /// set the tension.
        TensionerPreload,
    }
}

scene_enum! {
    /// Which way the chain goes round a sprocket when followed in scene order.
    pub enum Wrap {
        /// Counter-clockwise (the paper's "+").
        Ccw,
        /// Clockwise (the paper's "−").
        Cw,
    }
}

impl Wrap {
    /// +1 for counter-clockwise, −1 for clockwise.
    pub fn sign(self) -> f64 {
        match self {
            Self::Ccw => 1.0,
            Self::Cw => -1.0,
        }
    }
}

scene_enum! {
    /// What a sprocket does, without its parameters (the scene file's `role`;
    /// [`super::Role`] carries the parameters).
    pub enum RoleKind {
        /// Kinematically driven at a prescribed speed.
        Driver,
        /// Turns freely about a fixed centre.
        Free,
        /// Turns freely; its centre is moved to reach the pretension.
        Tensioner,
    }
}

scene_enum! {
    /// How the chain is advanced.
    pub enum Stepping {
        /// The plugin integrates the chain on its own arrays and writes poses back
        /// into rapier (the fast path).
        Substepped,
        /// rapier integrates every body; the plugin only supplies forces.
        Rapier,
    }
}

scene_enum! {
    /// Time integration scheme of the chain (see `crate::sim::integrate`).
    pub enum Integrator {
        /// v ← v + dt a(x, v); x ← x + dt v (rapier's own scheme). Order 1, one
        /// force evaluation per step.
        SymplecticEuler,
        /// Velocity Verlet (kick–drift–kick). Order 2, two evaluations per step.
        VelocityVerlet,
        /// Classical Runge–Kutta. Order 4, four evaluations per step.
        Rk4,
        /// Dormand–Prince 5(4), adaptive, with contact onset and separation
        /// located; `solver.dt_s` is then the largest step and the sample step.
        DormandPrince45,
        /// Symplectic Euler with the contact damping taken implicitly: stable
        /// where the Lankarani–Nikravesh damping at small approach speeds limits
        /// the explicit schemes. Order 1.
        ImplicitDamping,
        /// Velocity Verlet with one force evaluation per step and the contact
        /// damping taken by the trapezoidal rule: the contact damping does not
        /// bound its step, and a step costs about what a symplectic Euler step
        /// costs. Order 2.
        VerletImplicitDamping,
    }
}

impl Integrator {
    /// Nominal order of convergence.
    pub fn order(self) -> u32 {
        match self {
            Self::SymplecticEuler | Self::ImplicitDamping => 1,
            Self::VelocityVerlet | Self::VerletImplicitDamping => 2,
            Self::Rk4 => 4,
            Self::DormandPrince45 => 5,
        }
    }

    /// Whether the step size is chosen by an error estimate.
    pub fn is_adaptive(self) -> bool {
        self == Self::DormandPrince45
    }
}

/// The serde name of a unit variant: what `serialize_unit_variant` is
/// handed, a `&'static str` the derive wrote from the `rename_all` rule.
fn variant_name<T: Serialize>(value: &T) -> &'static str {
    value.serialize(VariantName).unwrap_or("")
}

/// A serializer that accepts only a unit variant and returns its name.
struct VariantName;

/// What [`VariantName`] returns for anything but a unit variant.
#[derive(Debug)]
struct NotUnitVariant;

impl std::fmt::Display for NotUnitVariant {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("not a unit variant")
    }
}

impl std::error::Error for NotUnitVariant {}

impl serde::ser::Error for NotUnitVariant {
    fn custom<M: std::fmt::Display>(_: M) -> Self {
        Self
    }
}

/// The serializer methods that refuse their value.
macro_rules! refuse {
    ($($method:ident($($arg:ty),*)),* $(,)?) => {
        $(fn $method(self, $(_: $arg),*) -> Result<Self::Ok, Self::Error> {
            Err(NotUnitVariant)
        })*
    };
}

impl serde::Serializer for VariantName {
    type Ok = &'static str;
    type Error = NotUnitVariant;
    type SerializeSeq = serde::ser::Impossible<Self::Ok, Self::Error>;
    type SerializeTuple = serde::ser::Impossible<Self::Ok, Self::Error>;
    type SerializeTupleStruct = serde::ser::Impossible<Self::Ok, Self::Error>;
    type SerializeTupleVariant = serde::ser::Impossible<Self::Ok, Self::Error>;
    type SerializeMap = serde::ser::Impossible<Self::Ok, Self::Error>;
    type SerializeStruct = serde::ser::Impossible<Self::Ok, Self::Error>;
    type SerializeStructVariant = serde::ser::Impossible<Self::Ok, Self::Error>;

    fn serialize_unit_variant(
        self,
        _: &'static str,
        _: u32,
        variant: &'static str,
    ) -> Result<Self::Ok, Self::Error> {
        Ok(variant)
    }

    refuse!(
        serialize_bool(bool),
        serialize_i8(i8),
        serialize_i16(i16),
        serialize_i32(i32),
        serialize_i64(i64),
        serialize_u8(u8),
        serialize_u16(u16),
        serialize_u32(u32),
        serialize_u64(u64),
        serialize_f32(f32),
        serialize_f64(f64),
        serialize_char(char),
        serialize_str(&str),
        serialize_bytes(&[u8]),
        serialize_none(),
        serialize_unit(),
        serialize_unit_struct(&'static str),
    );

    fn serialize_some<T: ?Sized + Serialize>(self, _: &T) -> Result<Self::Ok, Self::Error> {
        Err(NotUnitVariant)
    }

    fn serialize_newtype_struct<T: ?Sized + Serialize>(
        self,
        _: &'static str,
        _: &T,
    ) -> Result<Self::Ok, Self::Error> {
        Err(NotUnitVariant)
    }

    fn serialize_newtype_variant<T: ?Sized + Serialize>(
        self,
        _: &'static str,
        _: u32,
        _: &'static str,
        _: &T,
    ) -> Result<Self::Ok, Self::Error> {
        Err(NotUnitVariant)
    }

    fn serialize_seq(self, _: Option<usize>) -> Result<Self::SerializeSeq, Self::Error> {
        Err(NotUnitVariant)
    }

    fn serialize_tuple(self, _: usize) -> Result<Self::SerializeTuple, Self::Error> {
        Err(NotUnitVariant)
    }

    fn serialize_tuple_struct(
        self,
        _: &'static str,
        _: usize,
    ) -> Result<Self::SerializeTupleStruct, Self::Error> {
        Err(NotUnitVariant)
    }

    fn serialize_tuple_variant(
        self,
        _: &'static str,
        _: u32,
        _: &'static str,
        _: usize,
    ) -> Result<Self::SerializeTupleVariant, Self::Error> {
        Err(NotUnitVariant)
    }

    fn serialize_map(self, _: Option<usize>) -> Result<Self::SerializeMap, Self::Error> {
        Err(NotUnitVariant)
    }

    fn serialize_struct(
        self,
        _: &'static str,
        _: usize,
    ) -> Result<Self::SerializeStruct, Self::Error> {
        Err(NotUnitVariant)
    }

    fn serialize_struct_variant(
        self,
        _: &'static str,
        _: u32,
        _: &'static str,
        _: usize,
    ) -> Result<Self::SerializeStructVariant, Self::Error> {
        Err(NotUnitVariant)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_are_the_scene_file_names() {
        let names = |all: &[Integrator]| all.iter().map(|i| i.name()).collect::<Vec<_>>();
        assert_eq!(
            names(Integrator::ALL),
            [
                "symplectic_euler",
                "velocity_verlet",
                "rk4",
                "dormand_prince45",
                "implicit_damping",
                "verlet_implicit_damping"
            ]
        );
        assert_eq!(ContactLaw::LankaraniNikravesh.name(), "lankarani_nikravesh");
        assert_eq!(PretensionRule::RestLength.name(), "rest_length");
        assert_eq!(Wrap::from_name("cw"), Some(Wrap::Cw));
        assert_eq!(RoleKind::from_name("tensioner"), Some(RoleKind::Tensioner));
        assert_eq!(Stepping::from_name("sideways"), None);
    }

    #[test]
    fn serde_reads_the_same_names() {
        #[derive(Deserialize)]
        struct Row {
            integrator: Integrator,
        }
        let row: Row = toml::from_str("integrator = \"dormand_prince45\"").expect("parses");
        assert_eq!(row.integrator, Integrator::DormandPrince45);
    }

    #[cfg(feature = "cli")]
    #[test]
    fn clap_uses_the_same_names() {
        use clap::ValueEnum;
        for i in Integrator::ALL {
            let clap_name = i.to_possible_value().map(|v| v.get_name().to_owned());
            assert_eq!(clap_name.as_deref(), Some(i.name()));
        }
        for l in ContactLaw::ALL {
            let clap_name = l.to_possible_value().map(|v| v.get_name().to_owned());
            assert_eq!(clap_name.as_deref(), Some(l.name()));
        }
    }
}
