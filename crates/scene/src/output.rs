//! What accelviz writes: PNG images, and files written whole or not at all.

use std::path::{Path, PathBuf};

/// Why output could not be written.
#[derive(Debug, thiserror::Error)]
#[error("{path}: cannot write the file: {cause}")]
pub struct WriteError {
    /// The file meant to be written.
    pub path: String,
    /// What went wrong.
    pub cause: String,
}

/// An RGBA image (`width × height` pixels, row by row from the top left) as PNG bytes.
pub fn encode_png(width: usize, height: usize, rgba: &[[u8; 4]]) -> Result<Vec<u8>, String> {
    if rgba.len() != width * height {
        return Err(format!(
            "{} pixels given for a {width}×{height} image",
            rgba.len()
        ));
    }
    let (width, height) = (
        u32::try_from(width).map_err(|_| "the image is too wide".to_owned())?,
        u32::try_from(height).map_err(|_| "the image is too high".to_owned())?,
    );
    let mut bytes = Vec::new();
    let mut encoder = png::Encoder::new(&mut bytes, width, height);
    encoder.set_color(png::ColorType::Rgba);
    encoder.set_depth(png::BitDepth::Eight);
    let mut writer = encoder.write_header().map_err(|error| error.to_string())?;
    writer
        .write_image_data(rgba.as_flattened())
        .map_err(|error| error.to_string())?;
    writer.finish().map_err(|error| error.to_string())?;
    Ok(bytes)
}

/// Writes every file or none: each is written to a temporary file beside it, and only when
/// all are written are they renamed into place (a rename within a directory replaces the file
/// at once). On failure the temporary files are removed and no file named is touched.
pub fn write_all_or_nothing(files: &[(&Path, &[u8])]) -> Result<(), WriteError> {
    let fail = |path: &Path, cause: String| WriteError {
        path: path.display().to_string(),
        cause,
    };
    let mut written: Vec<(PathBuf, &Path)> = Vec::new();
    let remove_all = |written: &[(PathBuf, &Path)]| {
        for (temporary, _) in written {
            let _ = std::fs::remove_file(temporary);
        }
    };
    for (path, bytes) in files {
        let mut name = path
            .file_name()
            .ok_or_else(|| fail(path, "not a file name".into()))?
            .to_os_string();
        name.push(format!(".accelviz-{}.tmp", std::process::id()));
        let temporary = path.with_file_name(name);
        if let Err(error) = std::fs::write(&temporary, bytes) {
            let _ = std::fs::remove_file(&temporary);
            remove_all(&written);
            return Err(fail(path, error.to_string()));
        }
        written.push((temporary, path));
    }
    for (index, (temporary, path)) in written.iter().enumerate() {
        if let Err(error) = std::fs::rename(temporary, path) {
            remove_all(&written[index..]);
            return Err(fail(path, error.to_string()));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn png_round_trip_and_all_or_nothing() {
        let bytes = encode_png(2, 1, &[[255, 0, 0, 255], [0, 0, 255, 128]]).unwrap();
        assert_eq!(&bytes[1..4], b"PNG");
        assert!(encode_png(3, 1, &[[0; 4]]).is_err());

        let dir = std::env::temp_dir().join(format!("accelviz-output-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let good = dir.join("good.png");
        let missing = dir.join("no-such-dir").join("x.csv");
        let error = write_all_or_nothing(&[(&good, &bytes), (&missing, b"x")]).unwrap_err();
        assert!(
            error.to_string().contains("x.csv: cannot write the file"),
            "{error}"
        );
        // Nothing was left behind: no image, no temporary file.
        assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 0);
        write_all_or_nothing(&[(&good, &bytes)]).unwrap();
        assert_eq!(std::fs::read(&good).unwrap(), bytes);
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
