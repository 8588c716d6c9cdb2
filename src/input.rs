//! Reading the files a user names (scenes, course files, meshes, images), with a limit on
//! their size: a scene path that is `/dev/zero`, or a file far bigger than any scene, is one
//! clear error rather than a process the system kills for taking all its memory.

use std::io::Read;
use std::path::{Path, PathBuf};
use std::sync::Mutex;

/// Every file this process has opened through [`read_limited`] (scenes, course files,
/// meshes, textures, images), once each: a command checks its outputs against them
/// ([`crate::output::check_not_read`]), so that it never writes over one of its own inputs.
static READ: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

/// The files read so far (`READ`).
pub fn files_read() -> Vec<PathBuf> {
    READ.lock().map(|r| r.clone()).unwrap_or_default()
}

/// Starts the list of files read afresh: each command of the CLI does, so that a library
/// user running several in one process checks each one's outputs against its own inputs.
pub fn forget_reads() {
    if let Ok(mut read) = READ.lock() {
        read.clear();
    }
}

/// The most a text file of settings may hold: a native scene, a course `.ini` or XML
/// scenefile, a solid's spec (the biggest in `scenes/` and the course's are under 100 KiB).
pub const TEXT_LIMIT: u64 = 64 << 20;
/// The most an OBJ mesh may hold (about 50 million triangles).
pub const MESH_LIMIT: u64 = 4 << 30;
/// The most an image file may hold (a texture, or an image `diff` compares).
pub const IMAGE_LIMIT: u64 = 1 << 30;

/// The bytes of the file at `path`, or an I/O error; a file longer than `limit` bytes (found
/// from its size when it is a regular file, after reading `limit` bytes otherwise: a pipe
/// or a device) is an error of kind `InvalidData` that says so.
pub fn read_limited(path: &Path, limit: u64) -> std::io::Result<Vec<u8>> {
    let file = std::fs::File::open(path)?;
    if let Ok(mut read) = READ.lock() {
        if !read.iter().any(|p| p == path) {
            read.push(path.to_path_buf());
        }
    }
    let meta = file.metadata()?;
    let too_big = || {
        std::io::Error::new(
            std::io::ErrorKind::InvalidData,
            format!("larger than {}, the most such a file may hold", size(limit)),
        )
    };
    if meta.is_file() && meta.len() > limit {
        return Err(too_big());
    }
    let mut bytes = Vec::with_capacity(if meta.is_file() {
        meta.len() as usize
    } else {
        0
    });
    file.take(limit + 1).read_to_end(&mut bytes)?;
    if bytes.len() as u64 > limit {
        return Err(too_big());
    }
    Ok(bytes)
}

/// A limit in readable units: "64 MiB", "4 GiB".
fn size(bytes: u64) -> String {
    if bytes >= 1 << 30 {
        format!("{} GiB", bytes >> 30)
    } else {
        format!("{} MiB", bytes >> 20)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_file_over_the_limit_is_refused_and_one_within_it_read() {
        let file = Path::new(env!("CARGO_MANIFEST_DIR")).join("Cargo.toml");
        let len = std::fs::metadata(&file).unwrap().len();
        assert_eq!(read_limited(&file, len).unwrap().len() as u64, len);
        let e = read_limited(&file, len - 1).unwrap_err();
        assert_eq!(e.kind(), std::io::ErrorKind::InvalidData);
        assert!(
            e.to_string().contains("the most such a file may hold"),
            "{e}"
        );
    }

    /// A device that never ends is read only up to the limit.
    #[test]
    fn an_endless_device_stops_at_the_limit() {
        let e = read_limited(Path::new("/dev/zero"), 1 << 20).unwrap_err();
        assert!(e.to_string().contains("larger than 1 MiB"), "{e}");
    }
}
