//! Recordings into files: a new one at a path, and the continuation of a
//! resumed run's recording at its path. Writes no message itself: the
//! [`Recorder`] does.

use std::fs::File;
use std::io::BufWriter;
use std::path::Path;

use super::{RecordError, RecordMark, RecordOptions, Recorder, other_channels};
use crate::scene::Scene;

impl Recorder<BufWriter<File>> {
    /// Creates (or truncates) the file at `path` and starts recording into it.
    pub fn create(
        path: &Path,
        scene: &Scene,
        options: &RecordOptions,
    ) -> Result<Self, RecordError> {
        let file = File::create(path).map_err(|source| RecordError::Create {
            path: path.display().to_string(),
            source,
        })?;
        Self::new(BufWriter::new(file), scene, options)
    }

    /// Continues at `path` the recording of a run resumed from a checkpoint
    /// taken at `mark`. An MCAP file is not appended to: the earlier file is
    /// set aside (`PATH.before-resume`), the new one starts with its
    /// messages up to the mark ([`Recorder::continued`]), and the earlier
    /// file goes once they are written. If the process dies before that,
    /// the file set aside is still there for the next resume. Other
    /// channels than the run was recorded with are refused before any file
    /// is touched.
    ///
    /// # Errors
    /// [`RecordError::Continue`] for other channels, a file that cannot be
    /// set aside, read or removed, or an earlier recording that lacks the
    /// messages up to the mark; [`RecordError::Create`] when `path` cannot
    /// be created.
    pub fn continue_file(
        path: &Path,
        scene: &Scene,
        options: &RecordOptions,
        mark: &RecordMark,
    ) -> Result<Self, RecordError> {
        if mark.channels != options.channels.bits() {
            return Err(other_channels(mark, options));
        }
        let mut aside = path.as_os_str().to_owned();
        aside.push(".before-resume");
        let aside = std::path::PathBuf::from(aside);
        let failed = |what: &str, e: std::io::Error| RecordError::Continue(format!("{what}: {e}"));
        if !aside.exists() {
            std::fs::rename(path, &aside)
                .map_err(|e| failed("cannot set aside the recording the run was writing", e))?;
        }
        let earlier = std::fs::read(&aside).map_err(|e| {
            failed(
                &format!("cannot read the earlier recording {}", aside.display()),
                e,
            )
        })?;
        let file = File::create(path).map_err(|source| RecordError::Create {
            path: path.display().to_string(),
            source,
        })?;
        let recorder = Self::continued(BufWriter::new(file), scene, options, &earlier, mark)?;
        std::fs::remove_file(&aside)
            .map_err(|e| failed(&format!("cannot remove {}", aside.display()), e))?;
        Ok(recorder)
    }
}
