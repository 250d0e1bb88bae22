//! One relief process at a time in a results folder (a leaf): `DIR/.relief.lock`.
//!
//! `relief sweep` (the room grid too), `relief stability` and `relief report` hold the lock of
//! every folder they write or read results in for as long as they run, so that two of them
//! never append rows for the same cells or rewrite `results.csv` under each other. A second
//! process refuses with one line naming the holder (its pid, host and start), or waits for
//! it with `--wait`.
//!
//! The lock is the operating system's exclusive lock on the open file (std's
//! [`File::try_lock`](std::fs::File::try_lock): `flock` on Unix, `LockFileEx` on Windows),
//! not the file's existence: the system drops it the moment its holder exits, however it
//! exits, so a lock left by a killed process is never stale, and taking it over is the same
//! atomic call that takes a free one (two processes racing for a dead holder's folder cannot
//! both win). The file itself stays; while held it names the holder (`pid N, host H, started
//! at unix time T`), and it is emptied when released.

use std::path::{Path, PathBuf};

use crate::io::FileError;

/// Why a folder's lock could not be taken. One line each, naming the folder or lock file.
#[derive(Debug, thiserror::Error)]
pub enum LockError {
    /// Another relief process holds the lock (and the caller did not ask to wait).
    #[error("{} is in use by another relief process ({holder}): wait for it to finish, or pass --wait", dir.display())]
    Held {
        /// The folder.
        dir: PathBuf,
        /// What the lock file says of its holder (`pid N, host H, started at unix time T`).
        holder: String,
    },
    /// Something other than a regular file (a FIFO, a folder) stands where the lock file goes.
    #[error("cannot lock {}: {} is not a regular file", dir.display(), path.display())]
    NotRegular {
        /// The folder.
        dir: PathBuf,
        /// The lock file's path.
        path: PathBuf,
    },
    /// The lock file could not be opened or created.
    #[error("cannot lock {}: cannot open {}: {source}", dir.display(), path.display())]
    Open {
        /// The folder.
        dir: PathBuf,
        /// The lock file's path.
        path: PathBuf,
        /// The operating system's error.
        #[source]
        source: std::io::Error,
    },
    /// The operating system refused the lock call itself.
    #[error("cannot lock {}: {source}", path.display())]
    Lock {
        /// The lock file's path.
        path: PathBuf,
        /// The operating system's error.
        #[source]
        source: std::io::Error,
    },
    /// The folder could not be created, or the holder not written into the lock file.
    #[error(transparent)]
    File(#[from] FileError),
}

/// The lock file's name in a results folder.
pub(crate) const LOCK_FILE: &str = ".relief.lock";

/// How long [`FolderLock::take`] with `wait` sleeps between tries.
const POLL: std::time::Duration = std::time::Duration::from_millis(200);

/// A held folder lock; released when dropped (or when the process ends).
#[derive(Debug)]
pub struct FolderLock {
    file: std::fs::File,
    path: PathBuf,
}

impl FolderLock {
    /// Takes `dir`'s lock (creating `dir` and the lock file if missing). When another
    /// process holds it: an error naming the holder, or, with `wait`, a wait until it is
    /// released (`on_wait` is called once, with the holder, before the first sleep).
    pub fn take(dir: &Path, wait: bool, on_wait: &mut dyn FnMut(&str)) -> Result<FolderLock, LockError> {
        crate::io::create_dir_all(dir)?;
        let path = dir.join(LOCK_FILE);
        // A FIFO in the lock's place would block the open.
        if let Ok(meta) = std::fs::symlink_metadata(&path) {
            if !meta.is_file() {
                return Err(LockError::NotRegular { dir: dir.to_path_buf(), path });
            }
        }
        let file = std::fs::OpenOptions::new()
            .read(true)
            .write(true)
            .create(true)
            .truncate(false)
            .open(&path)
            .map_err(|source| LockError::Open { dir: dir.to_path_buf(), path: path.clone(), source })?;
        let mut told = false;
        loop {
            match try_flock(&file) {
                Ok(true) => break,
                Ok(false) if wait => {
                    if !told {
                        on_wait(&holder(&path));
                        told = true;
                    }
                    std::thread::sleep(POLL);
                }
                Ok(false) => return Err(LockError::Held { dir: dir.to_path_buf(), holder: holder(&path) }),
                Err(source) => return Err(LockError::Lock { path, source }),
            }
        }
        let lock = FolderLock { file, path };
        lock.write_holder().map_err(|e| FileError::write(&lock.path, e))?;
        Ok(lock)
    }

    /// The lock file's path.
    pub fn path(&self) -> &Path {
        &self.path
    }

    fn write_holder(&self) -> std::io::Result<()> {
        use std::io::{Seek, Write};
        let started =
            std::time::SystemTime::now().duration_since(std::time::UNIX_EPOCH).map(|d| d.as_secs()).unwrap_or(0);
        let text = format!("pid {}, host {}, started at unix time {started}\n", std::process::id(), host());
        let mut f = &self.file;
        f.set_len(0)?;
        f.seek(std::io::SeekFrom::Start(0))?;
        f.write_all(text.as_bytes())?;
        f.sync_data()?;
        Ok(())
    }
}

impl Drop for FolderLock {
    fn drop(&mut self) {
        // Emptied while still held; the kernel releases the lock when the file closes.
        let _ = self.file.set_len(0);
    }
}

/// Takes the locks of `dirs` (each folder once, in a fixed order so that two processes
/// waiting for the same folders cannot each hold what the other waits for).
pub fn take_all(dirs: &[&Path], wait: bool, on_wait: &mut dyn FnMut(&str)) -> Result<Vec<FolderLock>, LockError> {
    let mut keyed: Vec<(PathBuf, &Path)> = Vec::new();
    for d in dirs {
        crate::io::create_dir_all(d)?;
        let key = std::fs::canonicalize(d).unwrap_or_else(|_| d.to_path_buf());
        if !keyed.iter().any(|(k, _)| *k == key) {
            keyed.push((key, d));
        }
    }
    keyed.sort();
    keyed.into_iter().map(|(_, d)| FolderLock::take(d, wait, on_wait)).collect()
}

/// What the lock file says of its holder, for a message.
fn holder(path: &Path) -> String {
    match std::fs::read_to_string(path) {
        Ok(t) if !t.trim().is_empty() => relief_dsl::spec::echo(t.trim()),
        _ => "its pid not written yet".into(),
    }
}

fn host() -> String {
    std::fs::read_to_string("/etc/hostname")
        .ok()
        .map(|h| h.trim().to_string())
        .filter(|h| !h.is_empty())
        .or_else(|| std::env::var("HOSTNAME").ok())
        .unwrap_or_else(|| "unknown".into())
}

/// A non-blocking exclusive lock on `file`: `Ok(false)` when another open file holds it.
fn try_flock(file: &std::fs::File) -> std::io::Result<bool> {
    match file.try_lock() {
        Ok(()) => Ok(true),
        Err(std::fs::TryLockError::WouldBlock) => Ok(false),
        Err(std::fs::TryLockError::Error(e)) => Err(e),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_held_folder_is_refused_with_its_holder_and_free_again_once_released() {
        let dir = std::env::temp_dir().join(format!("relief-lock-unit-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        let first = FolderLock::take(&dir, false, &mut |_| {}).unwrap();
        let text = std::fs::read_to_string(first.path()).unwrap();
        assert!(text.starts_with(&format!("pid {}, host ", std::process::id())), "{text}");
        // A second open of the file (as another process would open it) is refused.
        let e = FolderLock::take(&dir, false, &mut |_| {}).unwrap_err();
        assert!(matches!(&e, LockError::Held { dir: d, .. } if *d == dir), "{e}");
        let e = e.to_string();
        assert!(
            e.contains("in use by another relief process") && e.contains(&format!("pid {}", std::process::id())),
            "{e}"
        );
        assert!(!e.contains('\n'), "{e}");
        // The same folder named twice is taken once.
        drop(first);
        assert_eq!(std::fs::read_to_string(dir.join(LOCK_FILE)).unwrap(), "", "emptied when released");
        let both = take_all(&[&dir, &dir.join("."), &dir.join("sub")], false, &mut |_| {}).unwrap();
        assert_eq!(both.len(), 2);
        drop(both);
        // A waiter gets it once the holder lets go.
        let held = FolderLock::take(&dir, false, &mut |_| {}).unwrap();
        let d2 = dir.clone();
        let waiter = std::thread::spawn(move || {
            let mut told = Vec::new();
            let l = FolderLock::take(&d2, true, &mut |h| told.push(h.to_string()));
            (l.is_ok(), told)
        });
        std::thread::sleep(std::time::Duration::from_millis(500));
        drop(held);
        let (ok, told) = waiter.join().unwrap();
        assert!(ok);
        assert_eq!(told.len(), 1, "{told:?}");
        let _ = std::fs::remove_dir_all(&dir);
    }
}
