//! The values of a PLY body, in either encoding: whitespace-separated text (ASCII) or packed
//! little- or big-endian binary. Every integer type fits an f64 exactly, so values come out
//! as f64 whatever their type; where they were is kept for errors.

use super::header::Scalar;

/// Where a value starts: a line and column in text, a byte offset in binary.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Location {
    LineColumn(usize, usize),
    Byte(usize),
}

/// A value that could not be read, and why.
#[derive(Debug)]
pub(super) struct BodyError {
    pub at: Location,
    pub message: String,
}

/// A stream of values of given types.
pub(super) trait Source {
    /// Reads one value of type `ty`.
    fn read(&mut self, ty: Scalar) -> Result<f64, BodyError>;
    /// Skips `n` values of type `ty`.
    fn skip(&mut self, ty: Scalar, n: usize) -> Result<(), BodyError>;
    /// Where the last value read starts (worked out only when an error needs it).
    fn last(&self) -> Location;
    /// The most values of type `ty` that the rest of the body could hold.
    fn capacity(&self, ty: Scalar) -> usize;
    /// After the last element: an error if anything but padding follows.
    fn finish(&mut self) -> Result<(), BodyError>;
}

/// Packed binary values.
pub(super) struct Binary<'a> {
    bytes: &'a [u8],
    pos: usize,
    last: usize,
    /// Byte offset of `bytes` in the file, for locations.
    base: usize,
    big_endian: bool,
}

impl<'a> Binary<'a> {
    pub(super) fn new(bytes: &'a [u8], base: usize, big_endian: bool) -> Self {
        Binary {
            bytes,
            pos: 0,
            last: 0,
            base,
            big_endian,
        }
    }

    fn take<const N: usize>(&mut self, ty: Scalar) -> Result<[u8; N], BodyError> {
        self.last = self.pos;
        match self.bytes.get(self.pos..self.pos + N) {
            Some(b) => {
                self.pos += N;
                let mut a: [u8; N] = b.try_into().expect("slice of length N");
                if self.big_endian {
                    a.reverse();
                }
                Ok(a)
            }
            None => Err(self.truncated(ty, 1)),
        }
    }

    fn truncated(&self, ty: Scalar, n: usize) -> BodyError {
        BodyError {
            at: Location::Byte(self.base + self.pos),
            message: format!(
                "the file ends here: expected {n} more {} value{} ({} byte{} left)",
                ty.name(),
                if n == 1 { "" } else { "s" },
                self.bytes.len() - self.pos,
                if self.bytes.len() - self.pos == 1 {
                    ""
                } else {
                    "s"
                },
            ),
        }
    }
}

impl Source for Binary<'_> {
    fn read(&mut self, ty: Scalar) -> Result<f64, BodyError> {
        // Bytes were reversed for big-endian data, so they are little-endian here.
        Ok(match ty {
            Scalar::Char => i8::from_le_bytes(self.take(ty)?) as f64,
            Scalar::UChar => u8::from_le_bytes(self.take(ty)?) as f64,
            Scalar::Short => i16::from_le_bytes(self.take(ty)?) as f64,
            Scalar::UShort => u16::from_le_bytes(self.take(ty)?) as f64,
            Scalar::Int => i32::from_le_bytes(self.take(ty)?) as f64,
            Scalar::UInt => u32::from_le_bytes(self.take(ty)?) as f64,
            Scalar::Float => f32::from_le_bytes(self.take(ty)?) as f64,
            Scalar::Double => f64::from_le_bytes(self.take(ty)?),
        })
    }

    fn skip(&mut self, ty: Scalar, n: usize) -> Result<(), BodyError> {
        self.last = self.pos;
        if n > self.capacity(ty) {
            return Err(self.truncated(ty, n));
        }
        self.pos += n * ty.size();
        Ok(())
    }

    fn last(&self) -> Location {
        Location::Byte(self.base + self.last)
    }

    fn capacity(&self, ty: Scalar) -> usize {
        (self.bytes.len() - self.pos) / ty.size()
    }

    /// Bytes after the last element are not read (some writers pad their files).
    fn finish(&mut self) -> Result<(), BodyError> {
        Ok(())
    }
}

/// Whitespace-separated text values.
pub(super) struct Ascii<'a> {
    bytes: &'a [u8],
    pos: usize,
    line: usize,
    line_start: usize,
    /// Start, line and line start of the last word read, and of the end of the one
    /// before (where "the file ends here" points).
    last: (usize, usize, usize),
    end: (usize, usize, usize),
}

impl<'a> Ascii<'a> {
    /// `bytes` is the body, whose first line is line `first_line` of the file.
    pub(super) fn new(bytes: &'a [u8], first_line: usize) -> Self {
        Ascii {
            bytes,
            pos: 0,
            line: first_line,
            line_start: 0,
            last: (0, first_line, 0),
            end: (0, first_line, 0),
        }
    }

    fn skip_space(&mut self) {
        while let Some(&b) = self.bytes.get(self.pos) {
            if !b.is_ascii_whitespace() {
                break;
            }
            self.pos += 1;
            if b == b'\n' {
                self.line += 1;
                self.line_start = self.pos;
            }
        }
    }

    /// Counting columns costs a pass over the line, so it waits for an error.
    fn location_of(&self, (start, line, line_start): (usize, usize, usize)) -> Location {
        let column = String::from_utf8_lossy(&self.bytes[line_start..start])
            .chars()
            .count()
            + 1;
        Location::LineColumn(line, column)
    }

    /// The next word; `last` marks where it starts.
    fn word(&mut self, ty: Scalar) -> Result<&'a str, BodyError> {
        self.skip_space();
        self.last = (self.pos, self.line, self.line_start);
        let start = self.pos;
        while self
            .bytes
            .get(self.pos)
            .is_some_and(|b| !b.is_ascii_whitespace())
        {
            self.pos += 1;
        }
        if start == self.pos {
            return Err(BodyError {
                at: self.location_of(self.end),
                message: format!("the file ends here: expected a {} value", ty.name()),
            });
        }
        self.end = (self.pos, self.line, self.line_start);
        match std::str::from_utf8(&self.bytes[start..self.pos]) {
            Ok(word) => Ok(word),
            Err(_) => Err(BodyError {
                at: self.last(),
                message: format!(
                    "expected a {} value, found bytes that are not text",
                    ty.name()
                ),
            }),
        }
    }
}

impl Source for Ascii<'_> {
    fn read(&mut self, ty: Scalar) -> Result<f64, BodyError> {
        let word = self.word(ty)?;
        let error = |message: String| BodyError {
            at: self.last(),
            message,
        };
        if ty.is_integer() {
            let (min, max) = ty.integer_range();
            match word.parse::<i64>() {
                Ok(v) if (min..=max).contains(&v) => Ok(v as f64),
                Ok(v) => Err(error(format!(
                    "{v} is out of range for {}: expected {min} to {max}",
                    ty.name()
                ))),
                Err(_) => Err(error(format!(
                    "expected a whole number ({}), found '{word}'",
                    ty.name()
                ))),
            }
        } else {
            // A float is read as one: through f64 it could round twice.
            let value = match ty {
                Scalar::Float => word.parse::<f32>().map(f64::from),
                _ => word.parse::<f64>(),
            };
            value.map_err(|_| error(format!("expected a number ({}), found '{word}'", ty.name())))
        }
    }

    fn skip(&mut self, ty: Scalar, n: usize) -> Result<(), BodyError> {
        for _ in 0..n {
            self.read(ty)?;
        }
        Ok(())
    }

    fn last(&self) -> Location {
        self.location_of(self.last)
    }

    /// Each value takes a character and a separator, but the last may end the file.
    fn capacity(&self, _ty: Scalar) -> usize {
        (self.bytes.len() - self.pos).div_ceil(2)
    }

    fn finish(&mut self) -> Result<(), BodyError> {
        self.skip_space();
        if self.pos == self.bytes.len() {
            return Ok(());
        }
        let at = self.location_of((self.pos, self.line, self.line_start));
        let rest = &self.bytes[self.pos..];
        let word_end = rest
            .iter()
            .position(|b| b.is_ascii_whitespace())
            .unwrap_or(rest.len())
            .min(20);
        Err(BodyError {
            at,
            message: format!(
                "expected the end of the file after the last element, found '{}'",
                String::from_utf8_lossy(&rest[..word_end])
            ),
        })
    }
}
