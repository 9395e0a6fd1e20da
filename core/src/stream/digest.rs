//! Digests: CRC-32 per frame, CRC-64 over the whole stream and over a
//! preset's parameters.

#[cfg(feature = "bitwise-crc")]
use crc::NoTable;
#[cfg(not(feature = "bitwise-crc"))]
use crc::Table;
use crc::{CRC_32_ISO_HDLC, CRC_64_XZ, Crc};
use serde::Serialize;

/// The CRC tables: slice-by-16 on a computer (a 64-bit target; 48 KB of
/// tables, several times faster), one table of 256 on an MCU or in the
/// browser, where flash and download size count, none with the feature
/// `bitwise-crc` (bit by bit, for the smallest flash). The same checksums.
#[cfg(all(target_pointer_width = "64", not(feature = "bitwise-crc")))]
type Slices = Table<16>;
#[cfg(all(not(target_pointer_width = "64"), not(feature = "bitwise-crc")))]
type Slices = Table<1>;
#[cfg(feature = "bitwise-crc")]
type Slices = NoTable;

/// The per-frame CRC's table: the stream digest's.
type FrameTable = Slices;

/// The per-frame check: CRC-32/ISO-HDLC (the zlib/Ethernet CRC).
pub(super) static FRAME_CRC: Crc<u32, FrameTable> = Crc::<u32, FrameTable>::new(&CRC_32_ISO_HDLC);
/// The stream and parameter digest: CRC-64/XZ.
static STREAM_CRC: Crc<u64, Slices> = Crc::<u64, Slices>::new(&CRC_64_XZ);

/// A running CRC-64/XZ over every byte of an encoded stream.
pub struct StreamDigest(crc::Digest<'static, u64, Slices>);

impl StreamDigest {
    /// An empty digest.
    #[must_use]
    pub fn new() -> StreamDigest {
        StreamDigest(STREAM_CRC.digest())
    }

    /// Feeds bytes.
    pub fn update(&mut self, bytes: &[u8]) {
        self.0.update(bytes);
    }

    /// The digest of everything fed so far.
    #[must_use]
    pub fn value(&self) -> u64 {
        self.0.clone().finalize()
    }

    /// The digest of a whole byte string.
    #[must_use]
    pub fn of(bytes: &[u8]) -> u64 {
        STREAM_CRC.checksum(bytes)
    }
}

impl Default for StreamDigest {
    fn default() -> Self {
        StreamDigest::new()
    }
}

impl core::fmt::Debug for StreamDigest {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        write!(f, "StreamDigest({:#018x})", self.value())
    }
}

/// A postcard serializer flavor that feeds a digest instead of a buffer.
pub struct ParamDigest(crc::Digest<'static, u64, Slices>);

impl core::fmt::Debug for ParamDigest {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str("ParamDigest")
    }
}

impl postcard::ser_flavors::Flavor for ParamDigest {
    type Output = u64;

    fn try_push(&mut self, data: u8) -> postcard::Result<()> {
        self.0.update(&[data]);
        Ok(())
    }

    fn try_extend(&mut self, data: &[u8]) -> postcard::Result<()> {
        self.0.update(data);
        Ok(())
    }

    fn finalize(self) -> postcard::Result<u64> {
        Ok(self.0.finalize())
    }
}

/// CRC-64/XZ of a parameter set's postcard encoding: the header's
/// `params` field. Parameters that postcard cannot encode digest to 0.
#[must_use]
pub fn params_digest<P: Serialize + ?Sized>(params: &P) -> u64 {
    postcard::serialize_with_flavor(params, ParamDigest(STREAM_CRC.digest())).unwrap_or(0)
}

#[cfg(test)]
mod tests {
    use super::{FRAME_CRC, StreamDigest};

    /// The catalogue's check values (the CRC of "123456789"), whichever
    /// table the build uses (`bitwise-crc` or not).
    #[test]
    fn the_digests_are_the_catalogued_crcs() {
        assert_eq!(FRAME_CRC.checksum(b"123456789"), 0xcbf4_3926);
        assert_eq!(StreamDigest::of(b"123456789"), 0x995d_c9bb_df19_39fa);
    }
}
