//! Image files: writing a film to disk, reading images back (`read`) and drawing figures
//! (`heatmap`, with the label font in `glyphs`).
//!
//! Writing a film to disk. The format follows the file extension: PNG (8-bit display
//! values, through the film's transfer), EXR (linear, 32-bit float or half) or PFM (linear
//! 32-bit float). A display-referred film's float files hold the linear light its PNG
//! shows, so every file of one render is the same picture. Every file is written
//! to a temporary name beside the target and renamed into place, so an interrupted write
//! never leaves a broken image under the requested name.

mod encode;
mod glyphs;
pub mod heatmap;
mod levels;
mod read;

pub use levels::Levels;
pub use read::{parse_pfm, read_image, ReadError};

use prism::render::Film;
use std::path::{Path, PathBuf};

/// The image file formats prism writes, chosen by extension.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ImageFormat {
    /// 8-bit display values through the film's transfer.
    Png,
    /// OpenEXR, linear light, in 32-bit floats or (`half`) 16-bit.
    Exr {
        /// 16-bit half floats instead of 32-bit floats.
        half: bool,
    },
    /// Portable float map, linear light in 32-bit floats.
    Pfm,
}

/// Why an image could not be written.
#[derive(Debug, thiserror::Error)]
pub enum OutputError {
    /// The extension names no format prism writes.
    #[error("{path}: unknown image format '.{ext}'; use .png, .exr or .pfm")]
    UnknownFormat {
        /// The file asked for.
        path: PathBuf,
        /// Its extension.
        ext: String,
    },
    /// The file name has no extension to choose a format by.
    #[error("{path}: no file extension; use .png, .exr or .pfm")]
    NoExtension {
        /// The file asked for.
        path: PathBuf,
    },
    /// Encoding or writing the file failed; the message says how.
    #[error("cannot write {path}: {message}")]
    Write {
        /// The file asked for.
        path: PathBuf,
        /// What went wrong.
        message: String,
    },
}

impl ImageFormat {
    /// The format the extension of `path` names, in any letter case.
    pub fn from_path(path: &Path) -> Result<Self, OutputError> {
        let ext =
            path.extension()
                .and_then(|e| e.to_str())
                .ok_or_else(|| OutputError::NoExtension {
                    path: path.to_path_buf(),
                })?;
        match ext.to_ascii_lowercase().as_str() {
            "png" => Ok(ImageFormat::Png),
            "exr" => Ok(ImageFormat::Exr { half: false }),
            "pfm" => Ok(ImageFormat::Pfm),
            _ => Err(OutputError::UnknownFormat {
                path: path.to_path_buf(),
                ext: ext.to_string(),
            }),
        }
    }
}

/// Encodes `film` in the format the extension of `path` names and writes it atomically.
pub fn write_image(path: &Path, film: &Film) -> Result<(), OutputError> {
    let format = ImageFormat::from_path(path)?;
    write_image_as(path, film, format)
}

/// Encodes `film` as `format` and writes it atomically, whatever the extension of `path`.
pub fn write_image_as(path: &Path, film: &Film, format: ImageFormat) -> Result<(), OutputError> {
    let err = |message: String| OutputError::Write {
        path: path.to_path_buf(),
        message,
    };
    let bytes = match format {
        ImageFormat::Png => encode::png(film),
        ImageFormat::Exr { half } => encode::exr(film, half),
        ImageFormat::Pfm => Ok(encode::pfm(film)),
    }
    .map_err(err)?;
    write_atomic(path, &bytes)
}

/// Writes an 8-bit RGB image (a figure, already display-encoded) as PNG, atomically.
pub fn write_png_rgb8(path: &Path, image: &heatmap::Rgb8) -> Result<(), OutputError> {
    let bytes = encode::png_rgb8(&image.data, image.width, image.height).map_err(|message| {
        OutputError::Write {
            path: path.to_path_buf(),
            message,
        }
    })?;
    write_atomic(path, &bytes)
}

/// The PNG file of an 8-bit RGB image (rows from the top), in memory: what a viewer hands
/// a browser to save, where no file is written.
pub fn png_rgb8_bytes(data: &[u8], width: u32, height: u32) -> Result<Vec<u8>, String> {
    encode::png_rgb8(data, width, height)
}

/// The temporary files of the writes in progress, for `abandon_writes`.
static UNFINISHED: std::sync::Mutex<Vec<std::path::PathBuf>> = std::sync::Mutex::new(Vec::new());

fn unfinished() -> std::sync::MutexGuard<'static, Vec<std::path::PathBuf>> {
    UNFINISHED.lock().unwrap_or_else(|e| e.into_inner())
}

/// Removes the temporary files of the writes in progress, for a process about to end at
/// once (`std::process::exit`, which runs no destructors: a second Ctrl-C), so that it
/// leaves no half-written file behind; call it just before the exit. No write starts
/// after it: one that tries waits for the exit.
pub fn abandon_writes() {
    let files = unfinished();
    for tmp in files.iter() {
        let _ = std::fs::remove_file(tmp);
    }
    // Held until the process ends, so that no write registers (and creates) a new file.
    std::mem::forget(files);
}

/// Writes `bytes` to a temporary name beside `path` and renames it into place.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), OutputError> {
    let err = |message: String| OutputError::Write {
        path: path.to_path_buf(),
        message,
    };
    let file_name = path
        .file_name()
        .ok_or_else(|| err("not a file name".into()))?;
    let mut tmp_name = std::ffi::OsString::from(".");
    tmp_name.push(file_name);
    tmp_name.push(format!(".{}.tmp", std::process::id()));
    let tmp = path.with_file_name(tmp_name);
    // Whatever fails (a full disk mid-write, a rename across devices), the temporary file
    // goes: a retry must not leave one more truncated file behind each time.
    unfinished().push(tmp.clone());
    let written = write_all_synced(&tmp, bytes).and_then(|()| std::fs::rename(&tmp, path));
    {
        let mut files = unfinished();
        if let Some(at) = files.iter().position(|f| *f == tmp) {
            files.swap_remove(at);
        }
    }
    written.map_err(|e| {
        let _ = std::fs::remove_file(&tmp);
        err(e.to_string())
    })
}

/// Writes `bytes` to a new file and waits until they reach the disk, so that a full disk
/// is reported here rather than lost at close.
fn write_all_synced(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    use std::io::Write;
    let mut file = std::fs::File::create(path)?;
    file.write_all(bytes)?;
    file.sync_all()
}

/// The film as 8-bit display values through its transfer (the sRGB curve, or the values
/// as they are), row-major RGB from the top-left: what PNG output contains.
pub fn to_rgb8(film: &Film) -> Vec<u8> {
    let levels = Levels::new(film.transfer);
    film.pixels
        .iter()
        .flat_map(|c| [c.x, c.y, c.z].map(|v| levels.encode8(v)))
        .collect()
}
