//! Scenes built in code: [`SceneBuilder`] gathers the parts of a
//! [`SceneFile`] and validates them at [`SceneBuilder::build`], exactly as a
//! file is validated. No TOML is written or read on the way.

use super::{
    ChainFile, ContactFile, EquilibriumFile, FieldError, GuideFile, ProfileKind, Scene, SceneError,
    SceneFile, SolverFile, SprocketFile,
};

/// Builds a [`Scene`] from its parts; see [`Scene::builder`].
///
/// ```
/// use chaindrive::scene::{Scene, SceneFile, L60MC_TOML};
///
/// // The paper's parts, put together in code.
/// let paper: SceneFile = toml::from_str(L60MC_TOML)?;
/// let scene = Scene::builder("the paper's drive, rebuilt")
///     .chain(paper.chain)
///     .contact(paper.contact)
///     .sprockets(paper.sprockets)
///     .build()?;
/// assert_eq!(scene.sprockets().len(), 4);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Debug)]
pub struct SceneBuilder {
    name: String,
    gravity_m_s2: [f64; 2],
    profile: ProfileKind,
    chain: Option<ChainFile>,
    contact: Option<ContactFile>,
    sprockets: Vec<SprocketFile>,
    solver: SolverFile,
    equilibrium: EquilibriumFile,
    guides: Vec<GuideFile>,
}

impl Scene {
    /// A builder for a scene named `name`: no gravity, circular profiles,
    /// the default solver and equilibrium settings; chain, contact and
    /// sprockets to be given.
    pub fn builder(name: impl Into<String>) -> SceneBuilder {
        SceneBuilder {
            name: name.into(),
            gravity_m_s2: [0.0, 0.0],
            profile: ProfileKind::Circular,
            chain: None,
            contact: None,
            sprockets: Vec::new(),
            solver: SolverFile::default(),
            equilibrium: EquilibriumFile::default(),
            guides: Vec::new(),
        }
    }
}

impl SceneBuilder {
    /// Gravity, m/s².
    pub fn gravity_m_s2(mut self, gravity_m_s2: [f64; 2]) -> Self {
        self.gravity_m_s2 = gravity_m_s2;
        self
    }

    /// Default tooth profile of every sprocket.
    pub fn profile(mut self, profile: ProfileKind) -> Self {
        self.profile = profile;
        self
    }

    /// The chain (required).
    pub fn chain(mut self, chain: ChainFile) -> Self {
        self.chain = Some(chain);
        self
    }

    /// The contact law (required).
    pub fn contact(mut self, contact: ContactFile) -> Self {
        self.contact = Some(contact);
        self
    }

    /// One more sprocket, after those already given (the order the chain visits them).
    pub fn sprocket(mut self, sprocket: SprocketFile) -> Self {
        self.sprockets.push(sprocket);
        self
    }

    /// More sprockets, after those already given.
    pub fn sprockets(mut self, sprockets: impl IntoIterator<Item = SprocketFile>) -> Self {
        self.sprockets.extend(sprockets);
        self
    }

    /// Solver settings.
    pub fn solver(mut self, solver: SolverFile) -> Self {
        self.solver = solver;
        self
    }

    /// Adds a guide (`[[guides]]`).
    pub fn guide(mut self, guide: GuideFile) -> Self {
        self.guides.push(guide);
        self
    }

    /// Static-equilibrium settings.
    pub fn equilibrium(mut self, equilibrium: EquilibriumFile) -> Self {
        self.equilibrium = equilibrium;
        self
    }

    /// The scene's file form (unchecked but for the required parts).
    pub fn file(self) -> Result<SceneFile, SceneError> {
        let missing = |path: &str| FieldError {
            path: path.to_owned(),
            message: "is required".to_owned(),
            location: None,
        };
        match (self.chain, self.contact) {
            (Some(chain), Some(contact)) => Ok(SceneFile {
                name: self.name,
                gravity_m_s2: self.gravity_m_s2,
                profile: self.profile.name().to_owned(),
                chain,
                contact,
                sprockets: self.sprockets,
                solver: self.solver,
                equilibrium: self.equilibrium,
                base_dir: None,
                given_tables: std::collections::BTreeMap::new(),
                tensioners: Vec::new(),
                guides: self.guides,
                checks: super::ChecksFile::default(),
                duty: Vec::new(),
            }),
            (chain, contact) => Err(SceneError::Invalid(
                [
                    chain.is_none().then(|| missing("chain")),
                    contact.is_none().then(|| missing("contact")),
                ]
                .into_iter()
                .flatten()
                .collect(),
            )),
        }
    }

    /// The validated scene: every problem is reported, with its field's path.
    pub fn build(self) -> Result<Scene, SceneError> {
        Scene::try_from(self.file()?)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn missing_parts_are_named() {
        let err = Scene::builder("empty").build().expect_err("incomplete");
        assert_eq!(err.lines(), ["chain: is required", "contact: is required"]);
    }

    #[test]
    fn a_built_scene_is_validated() {
        let paper: SceneFile = toml::from_str(crate::scene::L60MC_TOML).expect("parses");
        let err = Scene::builder("one sprocket")
            .chain(paper.chain)
            .contact(paper.contact)
            .sprocket(paper.sprockets[0].clone())
            .build()
            .expect_err("invalid");
        assert!(err.to_string().contains("at least 2 sprockets"), "{err}");
    }
}
