//! Writing files without ever leaving a half-written one: write to a temporary file in the
//! destination folder, then rename it into place.

use crate::error::{Error, Result};
use std::io::Write;
use std::path::{Path, PathBuf};

/// Checks that `path` can be written before any work is done (folder exists, not a folder).
pub fn check_writable(path: &Path, arg: &str) -> Result<()> {
    if path.is_dir() {
        return Err(Error::arg(
            arg,
            format!("{} is a directory, expected a file name", path.display()),
        ));
    }
    let dir = parent(path);
    if dir.exists() && !dir.is_dir() {
        return Err(Error::arg(
            arg,
            format!(
                "cannot write {}: {} is a file, not a folder",
                path.display(),
                dir.display()
            ),
        ));
    }
    if !dir.is_dir() {
        return Err(Error::arg(
            arg,
            format!(
                "cannot write {}: the folder {} does not exist",
                path.display(),
                dir.display()
            ),
        ));
    }
    // A folder that exists may still refuse files (permissions, a read-only or virtual file
    // system): find out now, with the temporary file the write would make (removed at once),
    // rather than after a render of minutes.
    temporary_in(dir).map(drop).map_err(|e| {
        // The folder is there, so "not found" means it takes no new files (/proc, /sys).
        let why = match e.kind() {
            std::io::ErrorKind::NotFound => "it does not take new files".to_string(),
            _ => reason(&e),
        };
        Error::arg(
            arg,
            format!(
                "cannot write {}: cannot write into the folder {}: {why}",
                path.display(),
                dir.display(),
            ),
        )
    })
}

/// A new temporary file in `dir`, hidden and named so that it is recognisably rtlab's, with
/// the usual mode of a new file.
fn temporary_in(dir: &Path) -> std::io::Result<tempfile::NamedTempFile> {
    let mut builder = tempfile::Builder::new();
    builder.prefix(".rtlab-").suffix(".tmp");
    // tempfile creates files 0600; an output file should get the usual mode (0666 less
    // the umask, applied by open(2)), like any file a command writes.
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        builder.permissions(std::fs::Permissions::from_mode(0o666));
    }
    builder.tempfile_in(dir)
}

/// Refuses to write over one of the command's own inputs: `inputs` holds each input's path
/// and what it is ("the scene", "your image"). The same file under another name counts
/// (a link, `./`, a symlink): files are compared by identity, not by name.
pub fn check_not_input(path: &Path, arg: &str, inputs: &[(&Path, &str)]) -> Result<()> {
    let Some(out) = identity(path) else {
        return Ok(()); // a file that does not exist yet is nobody's input
    };
    for (input, what) in inputs {
        if identity(input) == Some(out) {
            return Err(Error::arg(
                arg,
                format!(
                    "{} is {what}: writing there would destroy it (choose another name)",
                    path.display()
                ),
            ));
        }
    }
    Ok(())
}

/// Refuses to write over a file the command has read ([`crate::input::files_read`]): a
/// mesh or a texture the scene names, not only the scene itself.
pub fn check_not_read(path: &Path, arg: &str) -> Result<()> {
    let read = crate::input::files_read();
    let what: Vec<String> = read
        .iter()
        .map(|p| match p == path {
            true => "a file the scene reads".to_string(),
            false => format!("{}, a file the scene reads", p.display()),
        })
        .collect();
    let inputs: Vec<(&Path, &str)> = read
        .iter()
        .zip(&what)
        .map(|(p, w)| (p.as_path(), w.as_str()))
        .collect();
    check_not_input(path, arg, &inputs)
}

/// Refuses to write two of a command's outputs to one file (`outputs`: each path and its
/// argument), where the second would silently replace the first. Names are compared as
/// paths in their folders, so `a.png` and `./a.png` are one file, existing or not.
pub fn check_distinct(outputs: &[(&Path, &str)]) -> Result<()> {
    let key = |p: &Path| {
        let dir = std::fs::canonicalize(parent(p)).unwrap_or_else(|_| parent(p).to_path_buf());
        dir.join(p.file_name().unwrap_or_default())
    };
    for (i, (a, arg_a)) in outputs.iter().enumerate() {
        for (b, arg_b) in &outputs[..i] {
            if key(a) == key(b) {
                return Err(Error::arg(
                    *arg_a,
                    format!(
                        "{} is also {arg_b}'s file: one would replace the other (choose another name)",
                        a.display()
                    ),
                ));
            }
        }
    }
    Ok(())
}

/// What makes a file the same file under any name.
#[cfg(unix)]
fn identity(path: &Path) -> Option<(u64, u64)> {
    use std::os::unix::fs::MetadataExt;
    std::fs::metadata(path).ok().map(|m| (m.dev(), m.ino()))
}

#[cfg(not(unix))]
fn identity(path: &Path) -> Option<std::path::PathBuf> {
    std::fs::canonicalize(path).ok()
}

/// Refuses output names without the extension of what is written (`ext`, lower case, and
/// `what` it is, for the message), then checks that the name can be written.
pub fn check_extension(path: &Path, arg: &str, ext: &str, what: &str) -> Result<()> {
    match wrong_extension(path, ext, what) {
        Some(msg) if !path.is_dir() => Err(Error::arg(arg, msg)),
        _ => check_writable(path, arg),
    }
}

/// What is wrong with `path` as the name of a file of `what` with extension `ext`, if
/// anything (a course ini's `[IO] output` is checked with it too).
pub fn wrong_extension(path: &Path, ext: &str, what: &str) -> Option<String> {
    if path.as_os_str().is_empty() {
        return Some(format!("no file name given: give one, e.g. out.{ext}"));
    }
    let name = path.file_name().map(|n| n.to_string_lossy().to_string());
    match path
        .extension()
        .and_then(|e| e.to_str())
        .map(|e| e.to_ascii_lowercase())
    {
        Some(e) if e == ext => None,
        Some(e) => Some(format!("cannot write .{e} {what}: use a .{ext} file name")),
        None if name.is_some_and(|n| n.eq_ignore_ascii_case(&format!(".{ext}"))) => Some(format!(
            "{} is only an extension: give the file a name, e.g. out.{ext}",
            path.display()
        )),
        None => Some(format!(
            "{} has no extension: use a .{ext} file name",
            path.display()
        )),
    }
}

/// Creates `dir` and the folders above it, failing with a message in words.
fn create_folder(dir: &Path) -> Result<()> {
    std::fs::create_dir_all(dir)
        .map_err(|e| Error::io(dir, format!("cannot create the folder: {}", reason(&e))))
}

/// The folders made for an output not written yet (a course ini's `[IO] output`, whose
/// folders are made before the render, as the course's program does): unless
/// [`NewFolders::keep`] is called once the output is written, they are removed again when
/// this is dropped, deepest first and only while empty, so that a refused, failed or
/// interrupted command leaves no folder behind.
#[must_use = "dropped at once, the folders are removed at once"]
pub struct NewFolders(Vec<PathBuf>);

impl NewFolders {
    /// Creates `dir` and the folders above it, one at a time along the path as written,
    /// noting those it made itself (not those that existed, or that another process made
    /// meanwhile, or that a `..` leads back to). On an error, the message is
    /// the one `create_dir_all` gives, and the folders made so far are removed.
    pub fn create(dir: &Path) -> Result<NewFolders> {
        let mut made = NewFolders(Vec::new());
        let mut at = PathBuf::new();
        for part in dir.components() {
            at.push(part);
            match std::fs::create_dir(&at) {
                Ok(()) => made.0.insert(0, at.clone()), // deepest first
                Err(_) if at.is_dir() => {}
                Err(_) => {
                    create_folder(dir)?; // its message; it fails where this did
                    break;
                }
            }
        }
        Ok(made)
    }

    /// The output is written: the folders stay.
    pub fn keep(mut self) {
        self.0.clear();
    }
}

impl Drop for NewFolders {
    fn drop(&mut self) {
        for dir in &self.0 {
            let _ = std::fs::remove_dir(dir); // fails, and keeps it, unless empty
        }
    }
}

fn parent(path: &Path) -> &Path {
    match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    }
}

/// Writes `bytes` to `path` atomically.
/// Refuses to write at all once Ctrl-C was pressed ([`crate::interrupt`]).
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<()> {
    crate::interrupt::check()?;
    let dir = parent(path);
    let mut tmp = temporary_in(dir).map_err(|e| {
        Error::io(
            path,
            format!(
                "cannot write into the folder {}: {}",
                dir.display(),
                reason(&e)
            ),
        )
    })?;
    tmp.write_all(bytes)
        .map_err(|e| Error::io(path, format!("cannot write: {}", reason(&e))))?;
    tmp.as_file().sync_all().ok();
    crate::interrupt::check()?; // the temporary file is removed when `tmp` drops
    tmp.persist(path)
        .map_err(|e| Error::io(path, format!("cannot write: {}", reason(&e.error))))?;
    Ok(())
}

/// Why an I/O operation failed, in words: without the temporary file's random name (which
/// would make the message differ from run to run) and without the system's error number.
fn reason(e: &std::io::Error) -> String {
    use std::io::ErrorKind as K;
    match e.kind() {
        K::PermissionDenied => "permission denied".into(),
        K::NotFound => "no such file or directory".into(),
        K::ReadOnlyFilesystem => "read-only file system".into(),
        K::StorageFull => "no space left on device".into(),
        _ => match e.raw_os_error() {
            // "Not a directory (os error 20)" → "not a directory".
            Some(code) => {
                let text = std::io::Error::from_raw_os_error(code).to_string();
                let words = text.split(" (os error").next().unwrap_or(&text);
                let mut c = words.chars();
                c.next()
                    .map(|f| f.to_lowercase().chain(c).collect())
                    .unwrap_or_default()
            }
            None => e.kind().to_string(),
        },
    }
}

/// Encodes an RGB image as PNG and writes it atomically.
pub fn write_png(path: &Path, img: &image::RgbImage) -> Result<()> {
    let bytes = png_bytes(img).map_err(|e| Error::io(path, e))?;
    write_atomic(path, &bytes)
}

/// The PNG bytes [`write_png`] writes (the server answers with the same bytes).
pub fn png_bytes(img: &image::RgbImage) -> std::result::Result<Vec<u8>, String> {
    let mut bytes = Vec::new();
    img.write_to(
        &mut std::io::Cursor::new(&mut bytes),
        image::ImageFormat::Png,
    )
    .map_err(|e| format!("cannot encode PNG: {e}"))?;
    Ok(bytes)
}

/// Refuses output names whose extension rtlab cannot write.
pub fn check_png(path: &Path, arg: &str) -> Result<()> {
    check_extension(path, arg, "png", "images")
}

#[cfg(test)]
mod tests {
    use super::NewFolders;

    #[test]
    fn new_folders_are_removed_unless_kept_and_only_those_made() {
        let root = tempfile::tempdir().unwrap();
        let r = root.path();
        // Dropped: every folder it made goes, deepest first.
        drop(NewFolders::create(&r.join("a/b/c")).unwrap());
        assert!(!r.join("a").exists());
        // Kept: they stay.
        NewFolders::create(&r.join("a/b/c")).unwrap().keep();
        assert!(r.join("a/b/c").is_dir());
        // A folder that existed stays, only the new one below it goes.
        drop(NewFolders::create(&r.join("a/b/c/d")).unwrap());
        assert!(r.join("a/b/c").is_dir() && !r.join("a/b/c/d").exists());
        // A `..` leading back to a folder that existed: that folder is not the command's.
        std::fs::create_dir(r.join("keep")).unwrap();
        drop(NewFolders::create(&r.join("new/../keep")).unwrap());
        assert!(r.join("keep").is_dir() && !r.join("new").exists());
        // A folder that holds something by the time it is dropped stays.
        let f = NewFolders::create(&r.join("full")).unwrap();
        std::fs::write(r.join("full/x"), b"x").unwrap();
        drop(f);
        assert!(r.join("full/x").exists());
    }

    #[test]
    fn a_file_in_the_way_is_create_folders_error_and_leaves_nothing() {
        let root = tempfile::tempdir().unwrap();
        let r = root.path();
        std::fs::write(r.join("file"), b"x").unwrap();
        // "a" is made, then the file stops the path: create_folder's message, naming the
        // path, and "a" is removed again.
        let path = r.join("a/../file/deeper");
        let e = NewFolders::create(&path).err().expect("a file in the way");
        let said = e.to_string();
        assert!(
            said.starts_with(&format!("{}: cannot create the folder: ", path.display())),
            "{said}"
        );
        assert!(!r.join("a").exists());
    }
}
