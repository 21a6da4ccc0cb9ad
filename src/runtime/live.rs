//! Following a bake folder as it is baked again (`windloom bake --watch`, the editor's Live
//! export): a new bake answers once it has been read whole; a partial or broken one is
//! reported and the last good bake goes on answering.

use crate::load;
use crate::wind::{Bake, Options};
use crate::{Error, MANIFEST};
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// A bake folder, followed by its manifest's `sequence`.
#[derive(Debug)]
pub struct LiveBake {
    folder: PathBuf,
    bake: Arc<Bake>,
    /// The manifest the answering bake was read with.
    manifest: Vec<u8>,
    /// A manifest whose bake failed to read, not tried again until the manifest changes.
    failed: Option<Vec<u8>>,
    last_error: Option<String>,
}

impl LiveBake {
    /// Reads the bake in `folder` whole; an error when there is none to read.
    pub fn open(folder: impl AsRef<Path>, options: Options) -> Result<Self, Error> {
        let folder = folder.as_ref().to_path_buf();
        let (bake, manifest) = load::open(&folder, &options, load::ATTEMPTS)?;
        Ok(Self {
            folder,
            bake: Arc::new(bake),
            manifest,
            failed: None,
            last_error: None,
        })
    }

    /// The bake that answers now.
    pub fn bake(&self) -> &Bake {
        &self.bake
    }

    /// The bake that answers now, to share with other threads (a game that reads re-bakes
    /// off its main thread hands this over).
    pub fn shared(&self) -> Arc<Bake> {
        Arc::clone(&self.bake)
    }

    /// The folder followed.
    pub fn folder(&self) -> &Path {
        &self.folder
    }

    /// Why the newest bake in the folder is not the one answering, if it is not: the last
    /// [`Self::poll`] error, cleared by a successful read.
    pub fn last_error(&self) -> Option<&str> {
        self.last_error.as_deref()
    }

    /// Looks at the folder's manifest (a small read: call it every frame or on a timer);
    /// when it is another bake's, reads that bake whole and answers with it from now on.
    /// `Ok(true)` when a new bake answers, `Ok(false)` when nothing changed (or the new bake
    /// already failed and its manifest has not changed since), `Err` when the new bake could
    /// not be read (partial, broken): the last good bake goes on answering.
    ///
    /// It reads the new bake once and never waits: when another bake lands while it reads,
    /// it answers `Ok(false)` and reads the newest at the next poll.
    pub fn poll(&mut self) -> Result<bool, Error> {
        let path = self.folder.join(MANIFEST);
        let now = match load::read_manifest(&path) {
            Ok(b) => b,
            Err(e) => return Err(self.fail(None, e)),
        };
        if now == self.manifest || self.failed.as_ref() == Some(&now) {
            return Ok(false);
        }
        match load::open(&self.folder, &self.bake.options, 1) {
            Ok((bake, manifest)) => {
                let changed = manifest != self.manifest;
                self.bake = Arc::new(bake);
                self.manifest = manifest;
                self.failed = None;
                self.last_error = None;
                Ok(changed)
            }
            // Another bake landed while this one was read: the next poll reads it.
            Err(_) if load::read_manifest(&path).ok().as_deref() != Some(&now[..]) => Ok(false),
            Err(e) => Err(self.fail(Some(now), e)),
        }
    }

    /// Asks for another axes or edge rule from now on (and for the bakes to come).
    pub fn set_options(&mut self, options: Options) -> Result<(), Error> {
        if options.format != self.bake.options.format {
            let (bake, manifest) = load::open(&self.folder, &options, load::ATTEMPTS)?;
            self.bake = Arc::new(bake);
            self.manifest = manifest;
        } else {
            Arc::make_mut(&mut self.bake).options = options;
        }
        Ok(())
    }

    fn fail(&mut self, manifest: Option<Vec<u8>>, e: Error) -> Error {
        self.failed = manifest;
        self.last_error = Some(e.to_string());
        e
    }
}
