//! A pass is an object like any other for `vk::guard`: one being built, or a list of boxed ones
//! not yet in a graph, is guarded and destroyed as a pass.

use super::Pass;
use crate::vk::Device;

/// A pass being built is guarded like any other object (`vk::Guard`): it is destroyed as a pass.
impl<P: Pass + 'static> crate::vk::Destroy for P {
    unsafe fn destroy(self, device: &Device) {
        // SAFETY: per the contract.
        unsafe { Pass::destroy(Box::new(self), device) };
    }
}

impl crate::vk::Destroy for Box<dyn Pass> {
    unsafe fn destroy(self, device: &Device) {
        // SAFETY: per the contract.
        unsafe { Pass::destroy(self, device) };
    }
}
