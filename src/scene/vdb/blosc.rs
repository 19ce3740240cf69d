//! Blosc 1 decompression, for the value chunks of blosc-compressed OpenVDB files.
//!
//! OpenVDB (`io/Compression.cc`) compresses each node's values with c-blosc 1.x:
//! `blosc_compress_ctx(9, shuffle, typesize 4, ..., "lz4", blocksize = whole
//! chunk)`. This reads that frame format (c-blosc's `BLOSC_VERSION_FORMAT` 2):
//!
//! - a 16-byte header: format version (2), codec format version, flags (bit 0 byte
//!   shuffle, bit 1 stored uncompressed, bit 2 bit shuffle, bit 4 "blocks not split",
//!   bits 5-7 the codec: 0 BloscLZ, 1 LZ4 (and LZ4HC), 2 Snappy, 3 zlib, 4 Zstd), the
//!   type size, then little-endian u32s: uncompressed bytes, block size, compressed
//!   bytes (header included);
//! - unless stored uncompressed: one i32 offset per block (from the frame's start),
//!   and at each, the block as `nsplits` streams, each an i32 length and that many
//!   bytes (the stream stored raw when its length equals its uncompressed size).
//!   A block is split into one stream per byte of the type when the split flag is
//!   clear, the type is at most 16 bytes, the block holds at least 128 elements and
//!   it is not the last, shorter block (c-blosc 1.21, `blosc_d`);
//! - byte shuffle: a block of n elements of `typesize` bytes is stored as byte 0 of
//!   every element, then byte 1, ...; bytes past the last whole element are stored
//!   as they are.
//!
//! LZ4 blocks decode with `lz4_flex`, zlib with `flate2`. The other codecs are refused
//! by name (OpenVDB writes LZ4 only). Every length and offset is checked against the
//! frame before use; output never exceeds the size the caller expects.

use std::io::Read;

/// Decompresses the blosc frame `src` into exactly `expected` bytes.
pub fn decompress(src: &[u8], expected: usize) -> Result<Vec<u8>, String> {
    if src.len() < 16 {
        return Err(format!(
            "a blosc chunk of {} bytes is shorter than its 16-byte header",
            src.len()
        ));
    }
    let u32_at = |i: usize| u32::from_le_bytes([src[i], src[i + 1], src[i + 2], src[i + 3]]);
    let (version, flags, typesize) = (src[0], src[2], src[3] as usize);
    let (nbytes, blocksize, cbytes) = (u32_at(4) as usize, u32_at(8) as usize, u32_at(12) as usize);
    if version != 2 {
        return Err(format!(
            "blosc format version {version} (c-blosc 1.x writes version 2)"
        ));
    }
    if nbytes != expected {
        return Err(format!(
            "a blosc chunk holds {nbytes} bytes where {expected} are expected"
        ));
    }
    if cbytes > src.len() || cbytes < 16 {
        return Err(format!(
            "a blosc chunk claims {cbytes} compressed bytes but has {}",
            src.len()
        ));
    }
    let src = &src[..cbytes];
    if nbytes == 0 {
        return Ok(Vec::new());
    }
    if flags & 0x08 != 0 {
        return Err(format!("blosc flags {flags:#04x} from a later format"));
    }
    if flags & 0x02 != 0 {
        // Stored uncompressed after the header.
        if cbytes != nbytes + 16 {
            return Err(format!(
                "an uncompressed blosc chunk of {nbytes} bytes is {cbytes} bytes long"
            ));
        }
        return Ok(src[16..].to_vec());
    }
    if typesize == 0 || blocksize == 0 || blocksize > nbytes {
        return Err(format!(
            "blosc type size {typesize} and block size {blocksize} for {nbytes} bytes"
        ));
    }
    let codec = match flags >> 5 {
        1 => Codec::Lz4,
        3 => Codec::Zlib,
        c => {
            let name = ["BloscLZ", "LZ4", "Snappy", "zlib", "Zstd"]
                .get(c as usize)
                .copied()
                .unwrap_or("an unknown codec");
            return Err(format!(
                "blosc chunk compressed with {name} (wavetrace reads LZ4 and zlib, the \
                 codecs OpenVDB writes)"
            ));
        }
    };
    if flags & 0x04 != 0 {
        return Err("a bit-shuffled blosc chunk (OpenVDB writes byte shuffle)".into());
    }
    let nblocks = nbytes.div_ceil(blocksize);
    if 16 + 4 * nblocks > cbytes {
        return Err(format!(
            "a blosc chunk of {cbytes} bytes cannot hold the offsets of its {nblocks} blocks"
        ));
    }
    let dont_split = flags & 0x10 != 0;
    let shuffle = flags & 0x01 != 0 && typesize > 1;
    let mut out = vec![0u8; nbytes];
    let mut tmp = if shuffle {
        vec![0u8; blocksize]
    } else {
        Vec::new()
    };
    for j in 0..nblocks {
        let start = j * blocksize;
        let bsize = blocksize.min(nbytes - start);
        let leftover = bsize < blocksize;
        let nsplits = if !dont_split && typesize <= 16 && bsize / typesize >= 128 && !leftover {
            typesize
        } else {
            1
        };
        let neblock = bsize / nsplits;
        if neblock * nsplits != bsize {
            return Err(format!(
                "blosc block of {bsize} bytes does not split into {nsplits} streams"
            ));
        }
        let dest: &mut [u8] = if shuffle {
            &mut tmp[..bsize]
        } else {
            &mut out[start..start + bsize]
        };
        let mut offset = u32_at(16 + 4 * j) as usize;
        for s in 0..nsplits {
            if offset + 4 > cbytes {
                return Err(format!(
                    "blosc block {j} starts at byte {offset}, past the chunk's {cbytes}"
                ));
            }
            let len = i32::from_le_bytes([
                src[offset],
                src[offset + 1],
                src[offset + 2],
                src[offset + 3],
            ]);
            offset += 4;
            if len < 0 || len as usize > cbytes - offset {
                return Err(format!(
                    "blosc block {j} claims a stream of {len} bytes where {} remain",
                    cbytes - offset
                ));
            }
            let stream = &src[offset..offset + len as usize];
            let part = &mut dest[s * neblock..(s + 1) * neblock];
            if stream.len() == neblock {
                part.copy_from_slice(stream);
            } else {
                codec.decode(stream, part).map_err(|e| {
                    format!(
                        "blosc block {j}: {} stream does not decode: {e}",
                        codec.name()
                    )
                })?;
            }
            offset += len as usize;
        }
        if shuffle {
            unshuffle(typesize, &tmp[..bsize], &mut out[start..start + bsize]);
        }
    }
    Ok(out)
}

#[derive(Clone, Copy)]
enum Codec {
    Lz4,
    Zlib,
}

impl Codec {
    fn name(self) -> &'static str {
        match self {
            Codec::Lz4 => "an LZ4",
            Codec::Zlib => "a zlib",
        }
    }

    /// Decodes `src` into all of `dest`: an error unless it fills it exactly.
    fn decode(self, src: &[u8], dest: &mut [u8]) -> Result<(), String> {
        let n = match self {
            Codec::Lz4 => lz4_flex::block::decompress_into(src, dest).map_err(|e| e.to_string())?,
            Codec::Zlib => {
                let mut z = flate2::read::ZlibDecoder::new(src);
                let mut n = 0;
                while n < dest.len() {
                    match z.read(&mut dest[n..]).map_err(|e| e.to_string())? {
                        0 => break,
                        k => n += k,
                    }
                }
                // More data than the block holds is as wrong as less.
                if n == dest.len() && z.read(&mut [0u8; 1]).map_err(|e| e.to_string())? > 0 {
                    return Err(format!("more than {} bytes", dest.len()));
                }
                n
            }
        };
        if n != dest.len() {
            return Err(format!("{n} bytes where {} are expected", dest.len()));
        }
        Ok(())
    }
}

/// Undoes blosc's byte shuffle of one block (c-blosc `unshuffle_generic`).
fn unshuffle(typesize: usize, src: &[u8], dest: &mut [u8]) {
    let n = src.len() / typesize;
    for (i, element) in dest.chunks_exact_mut(typesize).enumerate() {
        for (b, byte) in element.iter_mut().enumerate() {
            *byte = src[b * n + i];
        }
    }
    let whole = n * typesize;
    dest[whole..].copy_from_slice(&src[whole..]);
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A blosc frame of one block, byte-shuffled, as c-blosc lays it out: typesize-4
    /// values split into 4 streams, each LZ4- or raw-coded.
    fn frame(values: &[f32], codec: u8, split: bool) -> Vec<u8> {
        let raw: Vec<u8> = values.iter().flat_map(|v| v.to_le_bytes()).collect();
        let n = values.len();
        let mut shuffled = vec![0u8; raw.len()];
        for i in 0..n {
            for b in 0..4 {
                shuffled[b * n + i] = raw[4 * i + b];
            }
        }
        let streams: Vec<&[u8]> = if split {
            shuffled.chunks(n).collect()
        } else {
            vec![&shuffled[..]]
        };
        let mut body = Vec::new();
        for s in streams {
            let coded = match codec {
                1 => lz4_flex::block::compress(s),
                _ => {
                    use std::io::Write;
                    let mut z = flate2::write::ZlibEncoder::new(Vec::new(), Default::default());
                    z.write_all(s).unwrap();
                    z.finish().unwrap()
                }
            };
            let coded = if coded.len() >= s.len() {
                s.to_vec()
            } else {
                coded
            };
            body.extend_from_slice(&(coded.len() as i32).to_le_bytes());
            body.extend_from_slice(&coded);
        }
        let flags = 0x01 | (codec << 5) | if split { 0 } else { 0x10 };
        let mut f = vec![2, 1, flags, 4];
        f.extend_from_slice(&(raw.len() as u32).to_le_bytes());
        f.extend_from_slice(&(raw.len() as u32).to_le_bytes());
        f.extend_from_slice(&((20 + body.len()) as u32).to_le_bytes());
        f.extend_from_slice(&20u32.to_le_bytes());
        f.extend_from_slice(&body);
        f
    }

    fn values() -> Vec<f32> {
        (0..512)
            .map(|i| if i % 7 < 3 { 0.0 } else { i as f32 * 0.25 })
            .collect()
    }

    fn as_f32(b: &[u8]) -> Vec<f32> {
        b.chunks_exact(4)
            .map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]]))
            .collect()
    }

    #[test]
    fn lz4_and_zlib_split_and_unsplit() {
        for codec in [1, 3] {
            for split in [true, false] {
                let f = frame(&values(), codec, split);
                let out = decompress(&f, 2048).unwrap();
                assert_eq!(as_f32(&out), values(), "codec {codec} split {split}");
            }
        }
    }

    #[test]
    fn memcpyed_frame() {
        let raw: Vec<u8> = (0..40u8).collect();
        let mut f = vec![2, 1, 0x02, 4];
        for v in [40u32, 40, 56] {
            f.extend_from_slice(&v.to_le_bytes());
        }
        f.extend_from_slice(&raw);
        assert_eq!(decompress(&f, 40).unwrap(), raw);
    }

    #[test]
    fn damaged_frames_are_errors() {
        let good = frame(&values(), 1, true);
        // Every truncation, and a wrong expected size.
        for cut in 0..good.len() {
            assert!(decompress(&good[..cut], 2048).is_err(), "cut at {cut}");
        }
        assert!(decompress(&good, 2044).unwrap_err().contains("2048"));
        // Every single-byte corruption either decodes to 2048 bytes or is an error.
        for i in 0..good.len() {
            for x in [0x01u8, 0x80, 0xff] {
                let mut bad = good.clone();
                bad[i] ^= x;
                if let Ok(out) = decompress(&bad, 2048) {
                    assert_eq!(out.len(), 2048);
                }
            }
        }
        let mut snappy = good.clone();
        snappy[2] = (snappy[2] & 0x1f) | (2 << 5);
        assert!(decompress(&snappy, 2048).unwrap_err().contains("Snappy"));
    }
}
