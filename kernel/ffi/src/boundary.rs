//! The one place where foreign pointers become Rust values.
//!
//! Every export runs its body through [`boundary`], which
//! - catches panics (`std::panic::catch_unwind`), so no unwind ever crosses into C or Fortran;
//! - turns an [`FfiError`] into its [`StossStatus`] and writes its message, NUL-terminated and
//!   truncated to the caller's capacity, into the caller-owned buffer (or clears it on
//!   success).
//!
//! Arrays arrive as raw pointers and are wrapped, after a NULL and alignment check, in
//! [`ArrayIn`] / [`ArrayOut`]. These read and write element by element through the raw pointer
//! (never through `&[T]` / `&mut [T]`), so arrays that a host passes twice or that overlap
//! (e.g. VUMAT `stressOld` and `stressNew` being the same array) are not undefined behaviour.

use std::ffi::c_char;
use std::marker::PhantomData;
use std::panic::{catch_unwind, AssertUnwindSafe};

use crate::status::{FfiError, StossStatus};

/// Run `body` behind the panic boundary; report its outcome as a status and a message.
///
/// On success the message buffer receives the empty string.
///
/// # Safety
/// `message` is NULL, or valid for writes of `capacity` bytes.
pub(crate) unsafe fn boundary<F>(message: *mut c_char, capacity: usize, body: F) -> StossStatus
where
    F: FnOnce() -> Result<(), FfiError>,
{
    let outcome = catch_unwind(AssertUnwindSafe(body));
    let (status, text) = match outcome {
        Ok(Ok(())) => (StossStatus::Ok, String::new()),
        Ok(Err(error)) => (error.status, error.message),
        Err(payload) => {
            let detail = if let Some(text) = payload.downcast_ref::<&str>() {
                (*text).to_owned()
            } else if let Some(text) = payload.downcast_ref::<String>() {
                text.clone()
            } else {
                "non-string panic payload".to_owned()
            };
            (
                StossStatus::Panic,
                format!("internal error (Rust panic caught at the C boundary): {detail}"),
            )
        }
    };
    // Writing the message cannot panic (no allocation, no indexing out of range), but keep it
    // behind the boundary too: nothing may unwind into the caller.
    let written = catch_unwind(AssertUnwindSafe(|| {
        // SAFETY: the caller guarantees `message` is NULL or valid for `capacity` bytes.
        unsafe { write_message(message, capacity, &text) }
    }));
    if written.is_err() {
        return StossStatus::Panic;
    }
    status
}

/// Copy `text` into the caller's buffer as a NUL-terminated string, truncated (at a UTF-8
/// character boundary) to `capacity - 1` bytes. Does nothing if `buffer` is NULL or
/// `capacity` is 0.
///
/// # Safety
/// `buffer` is NULL, or valid for writes of `capacity` bytes.
pub(crate) unsafe fn write_message(buffer: *mut c_char, capacity: usize, text: &str) {
    if buffer.is_null() || capacity == 0 {
        return;
    }
    let mut length = text.len().min(capacity - 1);
    while !text.is_char_boundary(length) {
        length -= 1;
    }
    let bytes = &text.as_bytes()[..length];
    // SAFETY: `buffer` is valid for `capacity > length` bytes (caller contract); the source is
    // a Rust string slice, which cannot overlap a buffer the caller owns exclusively for this
    // call.
    unsafe {
        std::ptr::copy_nonoverlapping(bytes.as_ptr().cast::<c_char>(), buffer, length);
        buffer.add(length).write(0);
    }
}

/// Check an optional output pointer (NULL allowed) for alignment before any state is
/// written, so that a rejected call has changed nothing.
pub(crate) fn check_optional_pointer<T>(pointer: *const T, field: &str) -> Result<(), FfiError> {
    if pointer.is_null() {
        Ok(())
    } else {
        check_pointer(pointer, field)
    }
}

/// Check a pointer argument that must not be NULL and must be aligned for `T`.
fn check_pointer<T>(pointer: *const T, field: &str) -> Result<(), FfiError> {
    if pointer.is_null() {
        return Err(FfiError::null(field));
    }
    if !pointer.is_aligned() {
        return Err(FfiError::new(
            StossStatus::MisalignedPointer,
            format!(
                "{field}: pointer {pointer:p} is not aligned to {} bytes",
                std::mem::align_of::<T>()
            ),
        ));
    }
    Ok(())
}

/// Read a `T` through a required pointer argument (a struct passed by address).
///
/// # Safety
/// `pointer` is NULL or points to a readable, initialised `T`.
pub(crate) unsafe fn read_struct<T: Copy>(pointer: *const T, field: &str) -> Result<T, FfiError> {
    check_pointer(pointer, field)?;
    // SAFETY: non-NULL and aligned (checked above); readable and initialised (caller contract).
    Ok(unsafe { pointer.read() })
}

/// Write a `T` through a required pointer argument.
///
/// # Safety
/// `pointer` is NULL or valid for writes of a `T`.
pub(crate) unsafe fn write_struct<T>(
    pointer: *mut T,
    value: T,
    field: &str,
) -> Result<(), FfiError> {
    check_pointer(pointer, field)?;
    // SAFETY: non-NULL and aligned (checked above); writable (caller contract).
    unsafe { pointer.write(value) };
    Ok(())
}

/// Write through an optional out-pointer (does nothing if NULL).
///
/// # Safety
/// `pointer` is NULL or valid for writes of a `T`.
pub(crate) unsafe fn write_optional<T>(
    pointer: *mut T,
    value: T,
    field: &str,
) -> Result<(), FfiError> {
    if pointer.is_null() {
        return Ok(());
    }
    // SAFETY: forwarded caller contract (non-NULL here).
    unsafe { write_struct(pointer, value, field) }
}

/// A caller-owned input array of `len` elements, read element by element.
#[derive(Clone, Copy)]
pub(crate) struct ArrayIn<'a, T> {
    pointer: *const T,
    len: usize,
    _borrow: PhantomData<&'a T>,
}

impl<'a, T: Copy> ArrayIn<'a, T> {
    /// A placeholder of length 0 (every access panics, caught at the boundary).
    pub(crate) fn empty() -> Self {
        Self {
            pointer: std::ptr::null(),
            len: 0,
            _borrow: PhantomData,
        }
    }

    /// Wrap a required array.
    ///
    /// # Safety
    /// `pointer` is NULL, or valid for reads of `len` initialised elements of `T` for `'a`.
    pub(crate) unsafe fn new(pointer: *const T, len: usize, field: &str) -> Result<Self, FfiError> {
        check_pointer(pointer, field)?;
        Ok(Self {
            pointer,
            len,
            _borrow: PhantomData,
        })
    }

    /// Wrap an optional array (`None` if NULL).
    ///
    /// # Safety
    /// As [`ArrayIn::new`].
    pub(crate) unsafe fn optional(
        pointer: *const T,
        len: usize,
        field: &str,
    ) -> Result<Option<Self>, FfiError> {
        if pointer.is_null() {
            return Ok(None);
        }
        // SAFETY: forwarded caller contract.
        unsafe { Self::new(pointer, len, field) }.map(Some)
    }

    /// Element `index`; panics (caught at the boundary) if `index >= len`.
    #[inline]
    pub(crate) fn get(&self, index: usize) -> T {
        assert!(index < self.len, "array index {index} out of {}", self.len);
        // SAFETY: `index < len` and the constructor's contract makes `len` elements readable.
        unsafe { self.pointer.add(index).read() }
    }

    /// Whether the array holds at least `n` elements.
    #[inline]
    pub(crate) fn covers(&self, n: usize) -> bool {
        n <= self.len
    }

    /// Element `index`, unchecked: for a loop whose bound was checked once with
    /// [`ArrayIn::covers`] (a checked access costs a reload of `len` after every write
    /// through an output array, which may alias it as far as the compiler knows).
    ///
    /// # Safety
    /// `index < len`.
    #[inline]
    pub(crate) unsafe fn get_unchecked(&self, index: usize) -> T {
        debug_assert!(index < self.len);
        // SAFETY: `index < len` (caller) and the constructor's contract.
        unsafe { self.pointer.add(index).read() }
    }
}

/// A caller-owned in/out array of `len` elements, read and written element by element.
pub(crate) struct ArrayOut<'a, T> {
    pointer: *mut T,
    len: usize,
    _borrow: PhantomData<&'a mut T>,
}

impl<'a, T: Copy> ArrayOut<'a, T> {
    /// A placeholder of length 0 (every access panics, caught at the boundary).
    pub(crate) fn empty() -> Self {
        Self {
            pointer: std::ptr::null_mut(),
            len: 0,
            _borrow: PhantomData,
        }
    }

    /// Wrap a required array.
    ///
    /// # Safety
    /// `pointer` is NULL, or valid for reads and writes of `len` elements of `T` for `'a`
    /// (elements that are read must be initialised).
    pub(crate) unsafe fn new(pointer: *mut T, len: usize, field: &str) -> Result<Self, FfiError> {
        check_pointer(pointer, field)?;
        Ok(Self {
            pointer,
            len,
            _borrow: PhantomData,
        })
    }

    /// Wrap an optional array (`None` if NULL).
    ///
    /// # Safety
    /// As [`ArrayOut::new`].
    pub(crate) unsafe fn optional(
        pointer: *mut T,
        len: usize,
        field: &str,
    ) -> Result<Option<Self>, FfiError> {
        if pointer.is_null() {
            return Ok(None);
        }
        // SAFETY: forwarded caller contract.
        unsafe { Self::new(pointer, len, field) }.map(Some)
    }

    /// Store `value` at `index`; panics (caught at the boundary) if `index >= len`.
    #[inline]
    pub(crate) fn set(&mut self, index: usize, value: T) {
        assert!(index < self.len, "array index {index} out of {}", self.len);
        // SAFETY: `index < len`; the constructor's contract makes the element writable.
        unsafe { self.pointer.add(index).write(value) }
    }

    /// Whether the array holds at least `n` elements.
    #[inline]
    pub(crate) fn covers(&self, n: usize) -> bool {
        n <= self.len
    }

    /// Element `index`, unchecked (see [`ArrayIn::get_unchecked`]).
    ///
    /// # Safety
    /// `index < len`.
    #[inline]
    pub(crate) unsafe fn get_unchecked(&self, index: usize) -> T {
        debug_assert!(index < self.len);
        // SAFETY: `index < len` (caller) and the constructor's contract.
        unsafe { self.pointer.add(index).read() }
    }

    /// Store `value` at `index`, unchecked (see [`ArrayIn::get_unchecked`]).
    ///
    /// # Safety
    /// `index < len`.
    #[inline]
    pub(crate) unsafe fn set_unchecked(&mut self, index: usize, value: T) {
        debug_assert!(index < self.len);
        // SAFETY: `index < len` (caller) and the constructor's contract.
        unsafe { self.pointer.add(index).write(value) }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn message_of(buffer: &[c_char]) -> String {
        let bytes: Vec<u8> = buffer
            .iter()
            .take_while(|&&c| c != 0)
            .map(|&c| c as u8)
            .collect();
        String::from_utf8(bytes).unwrap()
    }

    #[test]
    fn success_clears_the_message() {
        let mut buffer = [b'x' as c_char; 16];
        // SAFETY: the buffer is valid for its length.
        let status = unsafe { boundary(buffer.as_mut_ptr(), buffer.len(), || Ok(())) };
        assert_eq!(status, StossStatus::Ok);
        assert_eq!(buffer[0], 0);
    }

    #[test]
    fn errors_keep_their_status_and_message() {
        let mut buffer = [0 as c_char; 64];
        // SAFETY: the buffer is valid for its length.
        let status = unsafe {
            boundary(buffer.as_mut_ptr(), buffer.len(), || {
                Err(FfiError::new(StossStatus::ZeroPoints, "n: zero points"))
            })
        };
        assert_eq!(status, StossStatus::ZeroPoints);
        assert_eq!(message_of(&buffer), "n: zero points");
    }

    #[test]
    fn panics_become_a_status_not_an_unwind() {
        let mut buffer = [0 as c_char; 128];
        // SAFETY: the buffer is valid for its length.
        let status = unsafe {
            boundary(buffer.as_mut_ptr(), buffer.len(), || {
                let values: Vec<f64> = Vec::new();
                let index = values.len() + 3;
                if index > 2 {
                    panic!("deliberate test panic {index}");
                }
                Ok(())
            })
        };
        assert_eq!(status, StossStatus::Panic);
        let text = message_of(&buffer);
        assert!(text.contains("deliberate test panic 3"), "{text}");
        // A panic with a non-string payload.
        // SAFETY: as above.
        let status = unsafe {
            boundary(buffer.as_mut_ptr(), buffer.len(), || {
                std::panic::panic_any(42_u32);
            })
        };
        assert_eq!(status, StossStatus::Panic);
        assert!(message_of(&buffer).contains("non-string"));
    }

    #[test]
    fn out_of_range_array_access_is_caught() {
        let values = [1.0_f64, 2.0];
        // SAFETY: the buffer is NULL (no message); the array is valid for 2 elements.
        let status = unsafe {
            boundary(std::ptr::null_mut(), 0, || {
                let array = ArrayIn::new(values.as_ptr(), values.len(), "values")?;
                let _ = array.get(2);
                Ok(())
            })
        };
        assert_eq!(status, StossStatus::Panic);
    }

    #[test]
    fn messages_are_truncated_and_terminated() {
        let mut buffer = [b'x' as c_char; 6];
        // SAFETY: the buffer is valid for its length.
        unsafe { write_message(buffer.as_mut_ptr(), buffer.len(), "abcdefghij") };
        assert_eq!(message_of(&buffer), "abcde");
        assert_eq!(buffer[5], 0);
        // Never split a UTF-8 character: "Grü" is 4 bytes, capacity 4 leaves room for 3.
        let mut buffer = [b'x' as c_char; 4];
        // SAFETY: as above.
        unsafe { write_message(buffer.as_mut_ptr(), buffer.len(), "Grüneisen") };
        assert_eq!(message_of(&buffer), "Gr");
        // Capacity 1: only the terminator. Capacity 0 or NULL: nothing, no crash.
        let mut one = [b'x' as c_char; 1];
        // SAFETY: as above.
        unsafe { write_message(one.as_mut_ptr(), 1, "abc") };
        assert_eq!(one[0], 0);
        // SAFETY: capacity 0 / NULL buffers are never written.
        unsafe {
            write_message(one.as_mut_ptr(), 0, "abc");
            write_message(std::ptr::null_mut(), 10, "abc");
        }
    }

    #[test]
    fn null_and_misaligned_pointers_are_rejected() {
        // SAFETY: NULL and misaligned pointers are rejected before any access.
        unsafe {
            let error = ArrayIn::<f64>::new(std::ptr::null(), 3, "dt")
                .err()
                .unwrap();
            assert_eq!(error.status, StossStatus::NullPointer);
            assert!(error.message.starts_with("dt:"));
            let storage = [0.0_f64; 4];
            let misaligned = storage.as_ptr().cast::<u8>().add(1).cast::<f64>();
            let error = ArrayIn::new(misaligned, 2, "strain").err().unwrap();
            assert_eq!(error.status, StossStatus::MisalignedPointer);
            assert!(ArrayOut::<f64>::optional(std::ptr::null_mut(), 3, "x")
                .unwrap()
                .is_none());
        }
    }
}
