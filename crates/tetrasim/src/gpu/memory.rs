//! What memory a device offers (its heaps, and their budgets where the driver reports them
//! through `VK_EXT_memory_budget`), and whether what a plan needs fits: checked before
//! the first allocation, so a scene too large for the device is refused with both sizes
//! instead of failing half-built (or not failing, on drivers that overcommit).

use ash::vk;
use serde::Serialize;

use crate::error::{Error, Result};

/// One memory heap of a device.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub struct Heap {
    /// Its size [bytes].
    pub bytes: u64,
    /// What the process may still allocate from it now [bytes] (`VK_EXT_memory_budget`'s
    /// budget less its usage), when the driver reports it.
    pub available: Option<u64>,
    /// `VK_MEMORY_HEAP_DEVICE_LOCAL_BIT`.
    pub device_local: bool,
    /// Whether a host-visible memory type lives in it (the host can map it).
    pub host_visible: bool,
}

impl Heap {
    /// What the engine may take from it: the budget's remainder where known, else its size.
    pub fn offers(&self) -> u64 {
        self.available.unwrap_or(self.bytes)
    }
}

/// What a plan allocates, by where it lives.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize)]
pub struct MemoryNeeds {
    /// Device-local buffers [bytes].
    pub device_local: u64,
    /// Host-visible buffers (staging, readbacks, per-frame uploads) [bytes].
    pub host_visible: u64,
}

/// A device's memory heaps.
#[derive(Debug, Clone, Default, PartialEq, Eq, Serialize)]
pub struct DeviceMemory {
    /// Every heap, in the driver's order.
    pub heaps: Vec<Heap>,
}

impl DeviceMemory {
    /// Reads the heaps of `pd` (and their budgets where `budget`: the device has
    /// `VK_EXT_memory_budget`).
    ///
    /// # Safety
    /// `pd` must come from `instance`, which must be alive.
    pub(crate) unsafe fn query(
        instance: &ash::Instance,
        pd: vk::PhysicalDevice,
        budget: bool,
    ) -> Self {
        let mut budgets = vk::PhysicalDeviceMemoryBudgetPropertiesEXT::default();
        let mut props2 = vk::PhysicalDeviceMemoryProperties2::default();
        if budget {
            props2 = props2.push_next(&mut budgets);
        }
        // SAFETY: the caller vouches for `pd` and `instance`; `budgets` outlives the call.
        unsafe { instance.get_physical_device_memory_properties2(pd, &mut props2) };
        let props = props2.memory_properties;
        let types = &props.memory_types[..props.memory_type_count as usize];
        let heaps = (0..props.memory_heap_count as usize)
            .map(|h| {
                let heap = props.memory_heaps[h];
                let host_visible = types.iter().any(|t| {
                    t.heap_index as usize == h
                        && t.property_flags
                            .contains(vk::MemoryPropertyFlags::HOST_VISIBLE)
                });
                let available = budget.then(|| {
                    let (limit, used) = (budgets.heap_budget[h], budgets.heap_usage[h]);
                    limit.saturating_sub(used)
                });
                Heap {
                    bytes: heap.size,
                    available: available.filter(|&a| a > 0),
                    device_local: heap.flags.contains(vk::MemoryHeapFlags::DEVICE_LOCAL),
                    host_visible,
                }
            })
            .collect();
        Self { heaps }
    }

    /// The heap device-local buffers come from: the largest device-local one.
    fn device_heap(&self) -> Option<usize> {
        (0..self.heaps.len())
            .filter(|&h| self.heaps[h].device_local)
            .max_by_key(|&h| self.heaps[h].bytes)
    }

    /// The heap host-visible buffers come from: the largest host-visible one that is not
    /// device-local, else the largest host-visible one.
    fn host_heap(&self) -> Option<usize> {
        let visible = |h: &usize| self.heaps[*h].host_visible;
        (0..self.heaps.len())
            .filter(visible)
            .max_by_key(|&h| (!self.heaps[h].device_local, self.heaps[h].bytes))
    }

    /// Refuses `needs` where it does not fit: device-local buffers against the device-local
    /// heap (at most `limit` bytes of it, when given: `--device-memory`), host-visible ones
    /// against the host-visible heap, both against one heap where they share it (a CPU or
    /// integrated device). `device` names the device in the message.
    pub fn check(&self, needs: MemoryNeeds, limit: Option<u64>, device: &str) -> Result<()> {
        let limited = |offers: u64| limit.map_or(offers, |l| offers.min(l));
        let source = |offers: u64| match limit {
            Some(l) if l < offers => " (the --device-memory limit)",
            _ => "",
        };
        let refuse = |what: &str, needs: u64, offers: u64| {
            Err(Error::Memory(format!(
                "the vulkan backend needs {} of {what} for this problem, the device `{device}` \
                 offers {}{}",
                mib(needs),
                mib(limited(offers)),
                source(offers)
            )))
        };
        let Some(device_heap) = self.device_heap() else {
            // No heap says it is device-local (none should): nothing to compare with.
            return Ok(());
        };
        let offers = self.heaps[device_heap].offers();
        let host_heap = self.host_heap();
        if host_heap == Some(device_heap) {
            let all = needs.device_local + needs.host_visible;
            if all > limited(offers) {
                return refuse(
                    "memory (device-local and host-visible, one heap)",
                    all,
                    offers,
                );
            }
            return Ok(());
        }
        if needs.device_local > limited(offers) {
            return refuse("device-local memory", needs.device_local, offers);
        }
        if let Some(h) = host_heap {
            let offers = self.heaps[h].offers();
            if needs.host_visible > offers {
                return Err(Error::Memory(format!(
                    "the vulkan backend needs {} of host-visible memory for this problem, the \
                     device `{device}` offers {}",
                    mib(needs.host_visible),
                    mib(offers)
                )));
            }
        }
        Ok(())
    }

    /// Device-local bytes on offer (the device-local heap's budget or size; 0: none).
    pub fn device_local_offered(&self) -> u64 {
        self.device_heap().map_or(0, |h| self.heaps[h].offers())
    }
}

/// `bytes` in MiB, two decimals.
pub fn mib(bytes: u64) -> String {
    format!("{:.2} MiB", bytes as f64 / (1024.0 * 1024.0))
}

#[cfg(test)]
mod tests {
    use super::*;

    const MIB: u64 = 1 << 20;

    fn heap(mib: u64, device_local: bool, host_visible: bool) -> Heap {
        Heap {
            bytes: mib * MIB,
            available: None,
            device_local,
            host_visible,
        }
    }

    fn needs(device_local: u64, host_visible: u64) -> MemoryNeeds {
        MemoryNeeds {
            device_local: device_local * MIB,
            host_visible: host_visible * MIB,
        }
    }

    #[test]
    fn a_discrete_device_compares_each_kind_with_its_own_heap() {
        // An 80 GiB card: its VRAM, host memory it can map, and a small BAR window.
        let card = DeviceMemory {
            heaps: vec![
                heap(80 << 10, true, false),
                heap(64 << 10, false, true),
                heap(256, true, true),
            ],
        };
        assert!(card.check(needs(70 << 10, 1 << 10), None, "H100").is_ok());
        let err = card
            .check(needs(90 << 10, 0), None, "H100")
            .unwrap_err()
            .to_string();
        assert!(err.contains("92160.00 MiB of device-local memory"), "{err}");
        assert!(err.contains("`H100` offers 81920.00 MiB"), "{err}");
        let err = card
            .check(needs(1, 65 << 10), None, "H100")
            .unwrap_err()
            .to_string();
        assert!(err.contains("host-visible"), "{err}");
        // The limit binds below the heap and says so.
        let err = card
            .check(needs(2, 0), Some(MIB), "H100")
            .unwrap_err()
            .to_string();
        assert!(
            err.contains("offers 1.00 MiB (the --device-memory limit)"),
            "{err}"
        );
    }

    #[test]
    fn a_shared_heap_holds_both_kinds_at_once() {
        // lavapipe: one heap, device-local and host-visible.
        let cpu = DeviceMemory {
            heaps: vec![heap(1024, true, true)],
        };
        assert!(cpu.check(needs(600, 400), None, "llvmpipe").is_ok());
        let err = cpu
            .check(needs(600, 500), None, "llvmpipe")
            .unwrap_err()
            .to_string();
        assert!(err.contains("needs 1100.00 MiB"), "{err}");
    }

    #[test]
    fn a_budget_offers_what_is_left() {
        let mut busy = heap(1024, true, true);
        busy.available = Some(100 * MIB);
        let device = DeviceMemory { heaps: vec![busy] };
        assert_eq!(device.device_local_offered(), 100 * MIB);
        assert!(device.check(needs(101, 0), None, "busy").is_err());
        assert!(device.check(needs(99, 0), None, "busy").is_ok());
    }
}
