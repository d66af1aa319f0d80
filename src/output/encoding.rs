//! How the binary arrays of the VTK XML files (`.vtu` frames, `.vtp` surfaces) are stored in
//! their `<AppendedData>` section, as [`super::vtu::write_vtu`] and [`super::vtp::write_vtp`] write
//! them and [`super::vtu::read_vtu`] and [`super::vtp::read_vtp`] read them back.
//!
//! The block layouts follow VTK's XML file format ("VTK File Formats", VTK User's Guide,
//! section "Serial XML File Formats", and `vtkXMLDataParser`); all integers little-endian,
//! `header_type="UInt64"` (readers also take `UInt32`):
//!
//! | [`Encoding`] | `VTKFile` attributes | `AppendedData encoding` | one array's block |
//! |--------------|----------------------|-------------------------|-------------------|
//! | `zlib` (default) | `compressor="vtkZLibDataCompressor"` | `raw` | `[nb][nu][np][nc_1]…[nc_nb]` then the nb zlib streams |
//! | `base64`     | –                    | `base64`                | base64 of `[n]` followed by the n data bytes, encoded as one stream |
//! | `raw`        | –                    | `raw`                   | `[n]` then the n data bytes |
//!
//! `nb` is the number of blocks the array is cut into ([`ZLIB_BLOCK`] bytes each before
//! compression), `nu` the block size, `np` the size of the last block when it is shorter (0 when
//! every block is full), `nc_i` the compressed size of block i. A `DataArray`'s `offset` counts
//! bytes after the `_` marker (characters for `base64`).
//!
//! Which readers take which encoding: ParaView/VTK and meshio read all three; `vtkio` 0.7 (the
//! reader of splashsurf 0.14) reads only `base64` appended data (its `raw` variant is not
//! compiled in). `base64` is written uncompressed, with the byte count and the data in one
//! base64 stream, which is the layout `vtkio` decodes; the readers also take VTK's other
//! layouts (a separately encoded byte count; base64 of compressed blocks).

use std::io::Read;

use base64::Engine;
use base64::engine::{DecodePaddingMode, GeneralPurpose, GeneralPurposeConfig};
use flate2::Compression;
use flate2::write::ZlibEncoder;
use rayon::prelude::*;
use serde::Deserialize;

/// Storage of the binary arrays of a frame or surface file (`[output] encoding`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Encoding {
    /// Raw binary compressed with zlib (`vtkZLibDataCompressor`); the default: the smallest
    /// files (a 3D frame is about a third of its raw size), read by ParaView, VTK and meshio.
    #[default]
    Zlib,
    /// Uncompressed data encoded in base64 (4/3 of the raw size): pure ASCII, read by
    /// ParaView, VTK, meshio and by `vtkio`, hence splashsurf.
    Base64,
    /// Uncompressed raw binary: the fastest to write and read, read by ParaView, VTK and meshio.
    Raw,
}

impl Encoding {
    /// The name used in scene files (`"zlib"`, `"base64"`, `"raw"`).
    pub fn name(self) -> &'static str {
        match self {
            Encoding::Zlib => "zlib",
            Encoding::Base64 => "base64",
            Encoding::Raw => "raw",
        }
    }

    /// Every encoding, in the order the scene reference lists them.
    pub const ALL: [Encoding; 3] = [Encoding::Zlib, Encoding::Base64, Encoding::Raw];
}

/// Uncompressed size of one zlib block [bytes]: VTK's default block size, so that readers
/// keep at most this much per block in memory; blocks are compressed in parallel.
pub const ZLIB_BLOCK: usize = 1 << 15;

/// zlib level 1: on a 3D frame (the column dam break, 214,125 particles, arrays 10.5 MB) it
/// gives 32.4 % of the raw size against 32.3 % at level 6, in a third of the time.
const ZLIB_LEVEL: u32 = 1;

/// How the blocks of a file being read are laid out, from its `VTKFile` and `AppendedData`
/// attributes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct BlockFormat {
    /// Byte counts are `UInt64` (`true`) or `UInt32`.
    pub header_u64: bool,
    /// Blocks are zlib-compressed (`compressor="vtkZLibDataCompressor"`).
    pub zlib: bool,
    /// The appended section is base64 text (`encoding="base64"`).
    pub base64: bool,
}

impl BlockFormat {
    fn header_size(self) -> usize {
        if self.header_u64 { 8 } else { 4 }
    }

    /// The byte count at the start of `bytes`.
    fn header_value(self, bytes: &[u8]) -> Result<u64, String> {
        let short = || "truncated block header".to_owned();
        Ok(if self.header_u64 {
            u64::from_le_bytes(
                bytes
                    .get(..8)
                    .ok_or_else(short)?
                    .try_into()
                    .map_err(|_| short())?,
            )
        } else {
            u64::from(u32::from_le_bytes(
                bytes
                    .get(..4)
                    .ok_or_else(short)?
                    .try_into()
                    .map_err(|_| short())?,
            ))
        })
    }
}

/// The `<AppendedData>` section of a file being written: each array is encoded as it is
/// pushed, and its `offset` attribute returned.
#[derive(Debug)]
pub(crate) struct AppendedWriter {
    encoding: Encoding,
    data: Vec<u8>,
}

impl AppendedWriter {
    /// An empty section in `encoding`.
    pub fn new(encoding: Encoding) -> Self {
        Self {
            encoding,
            data: Vec::new(),
        }
    }

    /// Reserves room for arrays of `sizes` bytes, where their encoded size is known in advance
    /// (`raw`, `base64`), so that `data` does not grow by doubling.
    pub fn reserve(&mut self, sizes: &[usize]) {
        let encoded = |len: usize| match self.encoding {
            Encoding::Raw => 8 + len,
            Encoding::Base64 => (8 + len).div_ceil(3) * 4,
            Encoding::Zlib => 0,
        };
        let total: usize = sizes.iter().map(|&len| encoded(len)).sum();
        self.data.reserve_exact(total);
    }

    /// Appends one array given as its little-endian bytes; returns its `offset` attribute.
    pub fn push(&mut self, bytes: &[u8]) -> u64 {
        let offset = self.data.len() as u64;
        let count = (bytes.len() as u64).to_le_bytes();
        match self.encoding {
            Encoding::Raw => {
                self.data.extend_from_slice(&count);
                self.data.extend_from_slice(bytes);
            }
            Encoding::Base64 => {
                // The count and the array as one base64 stream, encoded straight into `data`.
                let mut w = base64::write::EncoderWriter::new(
                    &mut self.data,
                    &base64::engine::general_purpose::STANDARD,
                );
                // Writing into a Vec cannot fail.
                std::io::Write::write_all(&mut w, &count).expect("writing into memory");
                std::io::Write::write_all(&mut w, bytes).expect("writing into memory");
                w.finish().expect("writing into memory");
            }
            Encoding::Zlib => self.push_zlib(bytes),
        }
        offset
    }

    /// `[nb][nu][np][nc_1..nc_nb]` and the blocks, compressed in parallel.
    fn push_zlib(&mut self, bytes: &[u8]) {
        let blocks: Vec<Vec<u8>> = bytes
            .par_chunks(ZLIB_BLOCK)
            .map(|block| {
                let mut z = ZlibEncoder::new(
                    Vec::with_capacity(block.len() / 2 + 64),
                    Compression::new(ZLIB_LEVEL),
                );
                // Writing into a Vec cannot fail.
                std::io::Write::write_all(&mut z, block).expect("writing into memory");
                z.finish().expect("writing into memory")
            })
            .collect();
        let last = bytes.len() % ZLIB_BLOCK;
        let header = [blocks.len() as u64, ZLIB_BLOCK as u64, last as u64];
        for v in header.into_iter().chain(blocks.iter().map(|b| b.len() as u64)) {
            self.data.extend_from_slice(&v.to_le_bytes());
        }
        for b in &blocks {
            self.data.extend_from_slice(b);
        }
    }

    /// Attributes of `<VTKFile>` after `type`: byte order, header type, compressor.
    pub fn file_attributes(&self) -> &'static str {
        match self.encoding {
            Encoding::Zlib => {
                "version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\" compressor=\"vtkZLibDataCompressor\""
            }
            Encoding::Base64 | Encoding::Raw => {
                "version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\""
            }
        }
    }

    /// The whole `<AppendedData>` element, from its opening tag to its closing tag and newline.
    pub fn write_to(&self, w: &mut impl std::io::Write) -> std::io::Result<()> {
        let encoding = if self.encoding == Encoding::Base64 {
            "base64"
        } else {
            "raw"
        };
        write!(w, "  <AppendedData encoding=\"{encoding}\">\n   _")?;
        w.write_all(&self.data)?;
        w.write_all(b"\n  </AppendedData>\n")
    }
}

/// Little-endian bytes of `values`, each as `N` bytes by `to_bytes`.
pub(crate) fn le_bytes<T: Copy, const N: usize>(values: &[T], to_bytes: impl Fn(T) -> [u8; N]) -> Vec<u8> {
    let mut out = Vec::with_capacity(values.len() * N);
    for &v in values {
        out.extend_from_slice(&to_bytes(v));
    }
    out
}

/// Characters of base64 text that encode `bytes` bytes (with padding).
fn base64_len(bytes: usize) -> usize {
    bytes.div_ceil(3) * 4
}

/// Decodes standard base64, padding optional.
fn decode_base64(text: &[u8]) -> Result<Vec<u8>, String> {
    const LENIENT: GeneralPurpose = GeneralPurpose::new(
        &base64::alphabet::STANDARD,
        GeneralPurposeConfig::new()
            .with_decode_padding_mode(DecodePaddingMode::Indifferent)
            .with_decode_allow_trailing_bits(true),
    );
    LENIENT.decode(text).map_err(|e| format!("bad base64 data: {e}"))
}

/// `len` bytes (or characters) of `data` from `start`, or an error naming what runs past the end.
fn slice(data: &[u8], start: usize, len: usize) -> Result<&[u8], String> {
    start
        .checked_add(len)
        .and_then(|end| data.get(start..end))
        .ok_or_else(|| "block runs past the end of the appended data".to_owned())
}

/// Reads the bytes of the array whose block starts at `offset` in `appended` (the section
/// after `_`), in any layout of the [module table](self) and the variants [`BlockFormat`]
/// describes. Sizes come from the block headers and are checked against the data present;
/// `max_bytes` bounds what a header may claim (the caller's expected array size), so a
/// corrupt header cannot make the reader allocate more.
pub(crate) fn read_block(
    appended: &[u8],
    offset: usize,
    format: BlockFormat,
    max_bytes: u64,
) -> Result<Vec<u8>, String> {
    let h = format.header_size();
    match (format.base64, format.zlib) {
        (false, false) => {
            let n = format.header_value(slice(appended, offset, h)?)?;
            check_claim(n, max_bytes)?;
            Ok(slice(appended, offset + h, n as usize)?.to_vec())
        }
        (true, false) => {
            let head = slice(appended, offset, base64_len(h))?;
            let count = decode_base64(head)?;
            let n = format.header_value(&count)?;
            check_claim(n, max_bytes)?;
            if count.len() == h {
                // The byte count encoded on its own (padded to whole characters), then the data.
                decode_base64(slice(appended, offset + head.len(), base64_len(n as usize))?)
            } else {
                let all = decode_base64(slice(appended, offset, base64_len(h + n as usize))?)?;
                Ok(all[h..].to_vec())
            }
        }
        (false, true) => {
            let nb = format.header_value(slice(appended, offset, h)?)?;
            check_claim(nb, max_bytes.saturating_add(1))?;
            let head_len = h * (3 + nb as usize);
            let head = slice(appended, offset, head_len)?;
            let (sizes, total) = compressed_sizes(head, format)?;
            inflate_blocks(
                slice(appended, offset + head_len, total)?,
                head,
                &sizes,
                format,
                max_bytes,
            )
        }
        (true, true) => {
            let nb = format.header_value(&decode_base64(slice(appended, offset, base64_len(h))?)?)?;
            check_claim(nb, max_bytes.saturating_add(1))?;
            let head_chars = base64_len(h * (3 + nb as usize));
            let head = decode_base64(slice(appended, offset, head_chars)?)?;
            let (sizes, total) = compressed_sizes(&head, format)?;
            let body = decode_base64(slice(appended, offset + head_chars, base64_len(total))?)?;
            inflate_blocks(&body, &head, &sizes, format, max_bytes)
        }
    }
}

fn check_claim(n: u64, max_bytes: u64) -> Result<(), String> {
    if n > max_bytes {
        Err(format!(
            "block header claims {n} bytes, more than the {max_bytes} the array can hold"
        ))
    } else {
        Ok(())
    }
}

/// The compressed block sizes of a zlib header `[nb][nu][np][nc_1..]` and their sum.
fn compressed_sizes(head: &[u8], format: BlockFormat) -> Result<(Vec<usize>, usize), String> {
    let h = format.header_size();
    let values: Vec<u64> = head
        .chunks_exact(h)
        .map(|c| format.header_value(c))
        .collect::<Result<_, _>>()?;
    let sizes: Vec<usize> = values
        .get(3..)
        .ok_or("truncated compression header")?
        .iter()
        .map(|&s| usize::try_from(s).map_err(|_| "compressed block size too large".to_owned()))
        .collect::<Result<_, _>>()?;
    let total = sizes
        .iter()
        .try_fold(0usize, |a, &s| a.checked_add(s))
        .ok_or("compressed block sizes overflow")?;
    Ok((sizes, total))
}

/// Inflates the blocks of `body` (sizes `sizes`) and checks each against `nu`/`np` of `head`.
fn inflate_blocks(
    body: &[u8],
    head: &[u8],
    sizes: &[usize],
    format: BlockFormat,
    max_bytes: u64,
) -> Result<Vec<u8>, String> {
    let h = format.header_size();
    let nu = format.header_value(&head[h..])?;
    let np = format.header_value(&head[2 * h..])?;
    let nb = sizes.len() as u64;
    let total = match nb {
        0 => Some(0),
        _ if np == 0 => nb.checked_mul(nu),
        _ => (nb - 1).checked_mul(nu).and_then(|a| a.checked_add(np)),
    }
    .ok_or("compression header sizes overflow")?;
    check_claim(total, max_bytes)?;
    if np > nu {
        return Err(format!("last block of {np} bytes exceeds the block size {nu}"));
    }
    let mut out = Vec::with_capacity(total as usize);
    let mut start = 0;
    for (i, &size) in sizes.iter().enumerate() {
        let want = if i + 1 == sizes.len() && np != 0 { np } else { nu };
        let before = out.len();
        let block = body
            .get(start..start + size)
            .ok_or("compressed blocks run past the end of the data")?;
        let mut z = flate2::read::ZlibDecoder::new(block).take(want + 1);
        z.read_to_end(&mut out)
            .map_err(|e| format!("zlib block {i}: {e}"))?;
        if (out.len() - before) as u64 != want {
            return Err(format!(
                "zlib block {i} holds {} bytes, the header says {want}",
                out.len() - before
            ));
        }
        start += size;
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn format(encoding: Encoding) -> BlockFormat {
        BlockFormat {
            header_u64: true,
            zlib: encoding == Encoding::Zlib,
            base64: encoding == Encoding::Base64,
        }
    }

    #[test]
    fn every_encoding_reads_back_arrays_of_every_length() {
        let arrays: Vec<Vec<u8>> = [0usize, 1, 2, 3, 7, ZLIB_BLOCK - 1, ZLIB_BLOCK, 3 * ZLIB_BLOCK + 5]
            .iter()
            .map(|&n| (0..n).map(|i| (i * 7 % 251) as u8).collect())
            .collect();
        for encoding in Encoding::ALL {
            let mut w = AppendedWriter::new(encoding);
            let offsets: Vec<u64> = arrays.iter().map(|a| w.push(a)).collect();
            for (a, &off) in arrays.iter().zip(&offsets) {
                let back = read_block(&w.data, off as usize, format(encoding), a.len() as u64).unwrap();
                assert_eq!(&back, a, "{encoding:?}, {} bytes", a.len());
            }
        }
    }

    #[test]
    fn base64_with_a_separate_byte_count_and_compressed_base64_are_read() {
        let data: Vec<u8> = (0..100u8).collect();
        let b64 = |b: &[u8]| base64::engine::general_purpose::STANDARD.encode(b).into_bytes();
        // Byte count encoded on its own (one of VTK's layouts), UInt32 header.
        let mut text = b64(&100u32.to_le_bytes());
        text.extend(b64(&data));
        let f = BlockFormat {
            header_u64: false,
            zlib: false,
            base64: true,
        };
        assert_eq!(read_block(&text, 0, f, 100).unwrap(), data);
        // Compressed blocks in base64: header and blocks encoded apart, as VTK writes them.
        let mut z = ZlibEncoder::new(Vec::new(), Compression::default());
        std::io::Write::write_all(&mut z, &data).unwrap();
        let block = z.finish().unwrap();
        let head: Vec<u8> = [1u64, 100, 0, block.len() as u64]
            .iter()
            .flat_map(|v| v.to_le_bytes())
            .collect();
        let mut text = b64(&head);
        text.extend(b64(&block));
        let f = BlockFormat {
            header_u64: true,
            zlib: true,
            base64: true,
        };
        assert_eq!(read_block(&text, 0, f, 100).unwrap(), data);
    }

    #[test]
    fn corrupt_blocks_are_errors() {
        let data = vec![5u8; 1000];
        for encoding in Encoding::ALL {
            let mut w = AppendedWriter::new(encoding);
            w.push(&data);
            let f = format(encoding);
            // A header claiming more than the array holds, and a cut section.
            assert!(read_block(&w.data, 0, f, 999).is_err(), "{encoding:?}");
            assert!(
                read_block(&w.data[..w.data.len() - 3], 0, f, 1000).is_err(),
                "{encoding:?}"
            );
        }
        let mut w = AppendedWriter::new(Encoding::Zlib);
        w.push(&data);
        let last = w.data.len() - 1;
        w.data[last] ^= 0xff;
        assert!(read_block(&w.data, 0, format(Encoding::Zlib), 1000).is_err());
    }
}
