//! The per-thread scratch [`Data`].

use std::ptr::{self, NonNull};

use crate::ffi::{self, RawData};
use crate::{Error, Model};

/// Scratch space for the algorithms on one [`Model`] (Pinocchio's `Data`): joint placements
/// and Jacobian buffers. One per thread; `Send` but not `Sync`.
#[derive(Debug)]
pub struct Data {
    raw: NonNull<RawData>,
    model_id: u64,
    placements_valid: bool,
}

// SAFETY: the C++ data is plain heap memory owned by this value; it may move between threads.
// It is not `Sync`: every use that writes it takes `&mut Data`.
unsafe impl Send for Data {}

impl Data {
    /// Scratch data sized for `model`.
    ///
    /// # Errors
    /// [`Error::Load`], or [`Error::Backend`] if the allocation throws.
    pub fn new(model: &Model) -> Result<Data, Error> {
        let api = ffi::api()?;
        let mut raw: *mut RawData = ptr::null_mut();
        // SAFETY: `model.raw()` is a live model; `raw` is a live out-pointer.
        ffi::call("ks_pin_data_new", |e, n| unsafe {
            (api.data_new)(model.raw(), &mut raw, e, n)
        })?;
        Ok(Data {
            raw: NonNull::new(raw).expect("data_new succeeded"),
            model_id: model.id(),
            placements_valid: false,
        })
    }

    /// `Err` unless this data was made for `model`.
    pub(crate) fn check(&self, model: &Model) -> Result<(), Error> {
        if self.model_id == model.id() {
            Ok(())
        } else {
            Err(Error::DataModelMismatch)
        }
    }

    pub(crate) fn raw(&self) -> *const RawData {
        self.raw.as_ptr()
    }

    pub(crate) fn raw_mut(&mut self) -> *mut RawData {
        self.raw.as_ptr()
    }

    pub(crate) fn placements_valid(&self) -> bool {
        self.placements_valid
    }

    pub(crate) fn set_placements_valid(&mut self, valid: bool) {
        self.placements_valid = valid;
    }
}

impl Drop for Data {
    fn drop(&mut self) {
        if let Ok(api) = ffi::api() {
            // SAFETY: `raw` came from `data_new` and is freed exactly once, here.
            unsafe { (api.data_free)(self.raw.as_ptr()) };
        }
    }
}
