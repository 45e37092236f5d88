//! The buffers of a plan: which, and how large.

use crate::schedule::BufferId;

/// One planned buffer.
#[derive(Debug, Clone, PartialEq)]
pub struct BufferPlan {
    /// Which buffer.
    pub id: BufferId,
    /// Device-local size [bytes] (at least 4, as [`crate::gpu::Buffer`] allocates).
    pub bytes: u64,
    /// Size of its host-visible copy written every frame [bytes], 0 when there is none.
    pub readback_bytes: u64,
    /// Bytes the host writes into it before every frame's submit (the collider poses, a
    /// host-visible buffer), 0 for the others.
    pub upload_bytes: u64,
}
