//! One writer per output folder: `run` and `sweep` hold a lock on
//! `.morphogen.lock` in the folder they write, so two commands started
//! into one folder cannot mix their files (the second is refused), and the
//! holder removes the temporary files (`.morphogen-*`) that a killed
//! writer left there — with the lock held, none of them is anyone's.

use std::fs::{self, File, OpenOptions, TryLockError};
use std::path::Path;

use anyhow::{Context, Result, bail};

/// The lock file in a folder being written.
pub const LOCK_FILE: &str = ".morphogen.lock";

/// The prefix of the temporary files outputs are written through
/// ([`crate::atomic::OutputFile`]).
const TEMPORARY_PREFIX: &str = ".morphogen-";

/// The lock of an output folder, held until dropped (or the process ends,
/// however it ends).
#[derive(Debug)]
pub struct FolderLock {
    _file: File,
    /// Temporary files of an earlier writer removed, and their bytes.
    pub removed: (usize, u64),
}

impl FolderLock {
    /// Creates `dir` if needed, locks it and removes what a killed writer
    /// left in it.
    ///
    /// # Errors
    /// Another command holds the lock, or the folder cannot be created or
    /// written.
    pub fn take(dir: &Path) -> Result<FolderLock> {
        fs::create_dir_all(dir)
            .with_context(|| format!("cannot create output folder {}", dir.display()))?;
        let path = dir.join(LOCK_FILE);
        let file = OpenOptions::new()
            .create(true)
            .truncate(false)
            .write(true)
            .open(&path)
            .with_context(|| format!("cannot write in {}", dir.display()))?;
        match file.try_lock() {
            Ok(()) => {}
            Err(TryLockError::WouldBlock) => bail!(
                "another morphogen is writing into {} (it holds {LOCK_FILE}): wait for it to end, or give another --out",
                dir.display()
            ),
            Err(TryLockError::Error(e)) => {
                return Err(e).with_context(|| format!("cannot lock {}", path.display()));
            }
        }
        let removed = remove_temporary(dir)?;
        Ok(FolderLock {
            _file: file,
            removed,
        })
    }
}

/// Removes the temporary files in `dir`; their count and bytes.
fn remove_temporary(dir: &Path) -> Result<(usize, u64)> {
    let (mut count, mut bytes) = (0, 0);
    for entry in fs::read_dir(dir).with_context(|| format!("cannot list {}", dir.display()))? {
        let entry = entry.with_context(|| format!("cannot list {}", dir.display()))?;
        let is_temporary = entry
            .file_name()
            .to_str()
            .is_some_and(|n| n.starts_with(TEMPORARY_PREFIX));
        let Ok(meta) = entry.metadata() else { continue };
        if is_temporary && meta.is_file() {
            fs::remove_file(entry.path())
                .with_context(|| format!("cannot remove {}", entry.path().display()))?;
            count += 1;
            bytes += meta.len();
        }
    }
    Ok((count, bytes))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_second_writer_is_refused_and_left_overs_are_removed() {
        let tmp = tempfile::tempdir().unwrap();
        let dir = tmp.path().join("out");
        fs::create_dir(&dir).unwrap();
        fs::write(dir.join(".morphogen-abc123"), [0u8; 10]).unwrap();
        fs::write(dir.join("stream.bin"), b"kept").unwrap();
        let first = FolderLock::take(&dir).unwrap();
        assert_eq!(first.removed, (1, 10));
        assert!(dir.join("stream.bin").is_file());
        let second = FolderLock::take(&dir).unwrap_err().to_string();
        assert!(
            second.contains("another morphogen is writing into"),
            "{second}"
        );
        drop(first);
        assert_eq!(FolderLock::take(&dir).unwrap().removed, (0, 0));
    }
}
