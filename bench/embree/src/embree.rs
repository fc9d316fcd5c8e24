//! Embree 3 through the C shim (src/shim.c): a device, a scene of one triangle mesh, and
//! batch queries over flat ray arrays.

use std::ffi::c_void;

/// A ray as the shim reads it: origin, tnear, direction, tfar (16-byte halves, like
/// Embree's own `RTCRay`).
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct Ray {
    pub org: [f32; 3],
    pub tnear: f32,
    pub dir: [f32; 3],
    pub tfar: f32,
}

extern "C" {
    fn pe_device_new() -> *mut c_void;
    fn pe_device_release(device: *mut c_void);
    fn pe_device_error(device: *mut c_void) -> i32;
    fn pe_native_packets(device: *mut c_void, width: i32) -> i32;
    fn pe_scene_new(
        device: *mut c_void,
        positions: *const f32,
        vertex_count: usize,
        indices: *const u32,
        triangle_count: usize,
        quality: i32,
    ) -> *mut c_void;
    fn pe_scene_commit(scene: *mut c_void);
    fn pe_scene_release(scene: *mut c_void);
    fn pe_intersect1(
        s: *mut c_void,
        coherent: i32,
        r: *const Ray,
        n: usize,
        t: *mut f32,
        p: *mut u32,
    );
    fn pe_intersect8(
        s: *mut c_void,
        coherent: i32,
        r: *const Ray,
        n: usize,
        t: *mut f32,
        p: *mut u32,
    );
    fn pe_intersect16(
        s: *mut c_void,
        coherent: i32,
        r: *const Ray,
        n: usize,
        t: *mut f32,
        p: *mut u32,
    );
    fn pe_occluded1(s: *mut c_void, coherent: i32, r: *const Ray, n: usize, hit: *mut u8);
    fn pe_occluded8(s: *mut c_void, coherent: i32, r: *const Ray, n: usize, hit: *mut u8);
    fn pe_occluded16(s: *mut c_void, coherent: i32, r: *const Ray, n: usize, hit: *mut u8);
}

pub struct Device(*mut c_void);

impl Device {
    pub fn new() -> Device {
        // SAFETY: a NULL config asks for the defaults; the handle is checked below.
        let device = unsafe { pe_device_new() };
        assert!(!device.is_null(), "rtcNewDevice failed");
        Device(device)
    }

    /// Whether Embree's kernels for `width`-wide packets are native on this machine.
    pub fn native_packets(&self, width: usize) -> bool {
        // SAFETY: the device is live.
        unsafe { pe_native_packets(self.0, width as i32) != 0 }
    }

    fn check(&self, what: &str) {
        // SAFETY: the device is live.
        let code = unsafe { pe_device_error(self.0) };
        assert_eq!(code, 0, "Embree error {code} in {what}");
    }
}

impl Drop for Device {
    fn drop(&mut self) {
        // SAFETY: released once; scenes borrow the device, so none outlives it.
        unsafe { pe_device_release(self.0) }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Quality {
    Medium,
    High,
}

/// A committed scene. Embree allows any number of threads to trace it at once.
pub struct Scene<'d> {
    ptr: *mut c_void,
    _device: &'d Device,
}

// SAFETY: after rtcCommitScene, Embree's query functions are thread-safe on a scene.
unsafe impl Send for Scene<'_> {}
unsafe impl Sync for Scene<'_> {}

/// Which query function: single rays or `W`-wide packets of consecutive rays.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Width {
    One,
    Eight,
    Sixteen,
}

impl Width {
    pub fn lanes(self) -> usize {
        match self {
            Width::One => 1,
            Width::Eight => 8,
            Width::Sixteen => 16,
        }
    }
}

impl<'d> Scene<'d> {
    /// Copies the triangles into a new scene; `commit` builds it.
    pub fn new(
        device: &'d Device,
        positions: &[[f32; 3]],
        indices: &[[u32; 3]],
        q: Quality,
    ) -> Self {
        let quality = match q {
            Quality::Medium => 1,
            Quality::High => 2,
        };
        // SAFETY: the pointers and counts describe the two live slices, which the shim
        // copies before returning.
        let ptr = unsafe {
            pe_scene_new(
                device.0,
                positions.as_ptr().cast(),
                positions.len(),
                indices.as_ptr().cast(),
                indices.len(),
                quality,
            )
        };
        device.check("scene setup");
        Scene {
            ptr,
            _device: device,
        }
    }

    /// Builds the BVH (rtcCommitScene).
    pub fn commit(&self) {
        // SAFETY: the scene is live and not being traced.
        unsafe { pe_scene_commit(self.ptr) };
        self._device.check("rtcCommitScene");
    }

    /// Nearest hits: `t` (infinite for misses) and triangle index per ray.
    pub fn intersect(
        &self,
        width: Width,
        coherent: bool,
        rays: &[Ray],
        t: &mut [f32],
        prim: &mut [u32],
    ) {
        assert!(t.len() == rays.len() && prim.len() == rays.len());
        let f = match width {
            Width::One => pe_intersect1,
            Width::Eight => pe_intersect8,
            Width::Sixteen => pe_intersect16,
        };
        // SAFETY: the output slices are as long as the input, as asserted above.
        unsafe {
            f(
                self.ptr,
                coherent as i32,
                rays.as_ptr(),
                rays.len(),
                t.as_mut_ptr(),
                prim.as_mut_ptr(),
            )
        }
    }

    /// Any hit per ray.
    pub fn occluded(&self, width: Width, coherent: bool, rays: &[Ray], hit: &mut [u8]) {
        assert_eq!(hit.len(), rays.len());
        let f = match width {
            Width::One => pe_occluded1,
            Width::Eight => pe_occluded8,
            Width::Sixteen => pe_occluded16,
        };
        // SAFETY: the output slice is as long as the input, as asserted above.
        unsafe {
            f(
                self.ptr,
                coherent as i32,
                rays.as_ptr(),
                rays.len(),
                hit.as_mut_ptr(),
            )
        }
    }
}

impl Drop for Scene<'_> {
    fn drop(&mut self) {
        // SAFETY: released once.
        unsafe { pe_scene_release(self.ptr) }
    }
}
