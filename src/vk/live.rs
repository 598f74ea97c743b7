//! Live Vulkan objects: every handle meadow's `vk` layer creates is counted here when it is
//! created and again when it is destroyed, by object type, so a long run (the viewer's soak,
//! `make soak`) can show that nothing accumulates: created minus destroyed stays flat. Command
//! buffers and descriptor sets go with their pools and are not counted; the instance and the
//! device are not either (one each per run).

use std::collections::BTreeMap;
use std::sync::Mutex;

use ash::vk;

static LIVE: Mutex<BTreeMap<i32, i64>> = Mutex::new(BTreeMap::new());

fn add<T: vk::Handle + Copy>(handle: T, delta: i64) {
    if handle.as_raw() == 0 {
        return;
    }
    let mut live = LIVE.lock().unwrap_or_else(|poisoned| poisoned.into_inner());
    *live.entry(T::TYPE.as_raw()).or_insert(0) += delta;
}

/// Count `handle` as created (a null handle is not counted); returns it.
pub fn created<T: vk::Handle + Copy>(handle: T) -> T {
    add(handle, 1);
    handle
}

/// Count `handle` as destroyed (call it right before destroying; null is not counted).
pub fn destroyed<T: vk::Handle + Copy>(handle: T) {
    add(handle, -1);
}

/// Live objects of every type together.
pub fn total() -> i64 {
    LIVE.lock().unwrap_or_else(|poisoned| poisoned.into_inner()).values().sum()
}

/// Live objects by type (`vk::ObjectType` debug name), the types with any alive.
pub fn by_type() -> Vec<(String, i64)> {
    let live = LIVE.lock().unwrap_or_else(|poisoned| poisoned.into_inner());
    live.iter().filter(|(_, &n)| n != 0).map(|(&t, &n)| (format!("{:?}", vk::ObjectType::from_raw(t)), n)).collect()
}
