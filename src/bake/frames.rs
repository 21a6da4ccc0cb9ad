//! Frames streamed to disk as the solver makes them, and read back one at a time, so a bake's
//! memory does not grow with its frame count. The file is the raw format itself: little-endian
//! f32 pairs `[frame][row j][column i][x, z]`.

use super::error::BakeError;
use super::field::Field;
use std::fs::File;
use std::io::{BufReader, BufWriter, Read, Seek, SeekFrom, Write};
use std::path::{Path, PathBuf};

fn write_error(path: &Path, source: std::io::Error) -> BakeError {
    BakeError::Write {
        path: path.to_path_buf(),
        source,
    }
}

/// Appends frames to a file.
pub(crate) struct FrameWriter {
    path: PathBuf,
    file: BufWriter<File>,
    cells: usize,
    pub(crate) count: usize,
    /// Largest speed over the frames written, m/s.
    pub(crate) max_speed: f32,
}

impl FrameWriter {
    pub(crate) fn create(path: &Path, nx: usize, ny: usize) -> Result<Self, BakeError> {
        let file = File::create(path).map_err(|e| write_error(path, e))?;
        Ok(Self {
            path: path.to_path_buf(),
            file: BufWriter::with_capacity(1 << 20, file),
            cells: nx * ny,
            count: 0,
            max_speed: 0.0,
        })
    }

    pub(crate) fn push(&mut self, data: &[[f32; 2]]) -> Result<(), BakeError> {
        debug_assert_eq!(data.len(), self.cells);
        let mut bytes = Vec::with_capacity(data.len() * 8);
        for v in data {
            self.max_speed = self.max_speed.max(crate::num::hypot(v[0], v[1]));
            bytes.extend_from_slice(&v[0].to_le_bytes());
            bytes.extend_from_slice(&v[1].to_le_bytes());
        }
        self.file
            .write_all(&bytes)
            .map_err(|e| write_error(&self.path, e))?;
        self.count += 1;
        Ok(())
    }

    /// Flushes the frames to disk; returns the file's length.
    pub(crate) fn finish(self) -> Result<u64, BakeError> {
        let path = self.path;
        let file = self
            .file
            .into_inner()
            .map_err(|e| write_error(&path, e.into_error()))?;
        file.sync_all().map_err(|e| write_error(&path, e))?;
        Ok((self.count * self.cells * 8) as u64)
    }
}

/// Reads frames back by index.
pub(crate) struct FrameReader {
    path: PathBuf,
    file: BufReader<File>,
    nx: usize,
    ny: usize,
    buf: Vec<u8>,
}

impl FrameReader {
    pub(crate) fn open(path: &Path, nx: usize, ny: usize) -> Result<Self, BakeError> {
        let file = File::open(path).map_err(|e| write_error(path, e))?;
        Ok(Self {
            path: path.to_path_buf(),
            file: BufReader::with_capacity(1 << 20, file),
            nx,
            ny,
            buf: vec![0; nx * ny * 8],
        })
    }

    pub(crate) fn read(&mut self, k: usize) -> Result<Field, BakeError> {
        let offset = (k * self.buf.len()) as u64;
        self.file
            .seek(SeekFrom::Start(offset))
            .and_then(|_| self.file.read_exact(&mut self.buf))
            .map_err(|e| write_error(&self.path, e))?;
        let f = |c: &[u8]| f32::from_le_bytes([c[0], c[1], c[2], c[3]]);
        let data = self
            .buf
            .chunks_exact(8)
            .map(|c| [f(&c[..4]), f(&c[4..])])
            .collect();
        Ok(Field {
            nx: self.nx,
            ny: self.ny,
            data,
        })
    }
}
