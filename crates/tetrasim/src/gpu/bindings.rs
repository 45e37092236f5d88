// The one list of the simulation's descriptor bindings (set 0), included as text twice:
// `gpu::layout::binding` makes a `u32` constant of each for the host, and build.rs compiles
// every shader with a macro `B_<NAME>` of the same value (glsl/common/bindings.glsl uses
// them). A new buffer's binding is one entry here; neither side can drift from the other.
// Only `///` docs and `NAME = number,` entries belong in this file.
bindings! {
    /// vec4 per node: position [m], w = inverse mass [1/kg].
    POSITIONS = 0,
    /// vec4 per node: velocity [m/s], w = mass [kg].
    VELOCITIES = 1,
    /// vec4 per node: the step's force F [N] (a float view for atomics), w = the floor's
    /// normal force [N], already part of F.y (physics/integrate.glsl).
    FORCES = 2,
    /// vec4 per node: the current iteration's summed constraint forces [N].
    CONSTRAINT_SUM = 3,
    /// [`super::GpuSpring`] per spring.
    SPRINGS = 4,
    /// uvec4 per tet: node indices, positively oriented.
    TETS = 5,
    /// float per tet: rest volume [m^3].
    REST_VOLUMES = 6,
    /// float per node: its number of constraints of the method's kind `d_k`, for the combine
    /// mode's factors (physics/implicit.glsl).
    CONSTRAINT_DEGREE = 7,
    /// Node -> springs CSR offsets (N + 1).
    NODE_SPRING_OFFSETS = 8,
    /// Node -> springs CSR items.
    NODE_SPRING_ITEMS = 9,
    /// [`super::VolumePartial`] per volume_sum workgroup.
    VOLUME_PARTIALS = 10,
    /// Divergence status (16 bytes, check.comp): flags (1 non-finite, 2 too fast), first bad
    /// node (u32::MAX when none), speed limit [m/s], the fastest too-fast node's speed [m/s]
    /// (f32 bits); when the frame measures contact 16 bytes more (contact_measure.comp,
    /// zeroed at each frame's start): the nodes a collider pushed in the last step, the
    /// pushing body contacts, the deepest penetration [m] (f32 bits), a pad word.
    STATUS = 11,
    /// u32 per constraint: the constraints in group order (gather path: Gauss-Seidel by
    /// colour groups, no atomics; groups are contiguous ranges; with several sweeps per
    /// iteration the sweeps lie one after another, from `pc.member_first`).
    GROUP_MEMBERS = 12,
    /// vec4 per constraint corner, in group order: `-lambda grad_k C` (gather path, from
    /// `pc.slot_first`).
    CONTRIBUTIONS = 13,
    /// Per group and node, slot CSR offsets (`groups * N + 1`, gather path; the groups of
    /// all sweeps numbered together).
    NODE_SLOT_OFFSETS = 14,
    /// Slot CSR items: indices into the contributions (gather path).
    NODE_SLOT_ITEMS = 15,
    /// [`super::GpuGlobalObject`] per object (global volume constraints).
    GLOBAL_OBJECTS = 16,
    /// u32 per surface node: its node index, object after object.
    SURFACE_NODES = 17,
    /// uvec4 per outward boundary face: three node indices, 0.
    SURFACE_FACES = 18,
    /// Surface node (its position in SurfaceNodes) -> face corners CSR offsets.
    NODE_FACE_OFFSETS = 19,
    /// Surface node -> face corners CSR items (`3 face + corner`).
    NODE_FACE_ITEMS = 20,
    /// vec4 per surface node: `grad_k C_g` of its object at x(t) [m^2], w = its inverse mass
    /// (written by global_volume_prepare once per step).
    SURFACE_GRADIENTS = 21,
    /// vec4 per chunk of each object (glsl/common/global_chunk.glsl): the chunk's shares of
    /// the object's volume `sum face_volume` [m^3] and of `A = sum_k w_k |grad_k C_g|^2`
    /// (global_volume_prepare, once per step), and of this iteration's `B`
    /// (global_volume_sum); global_volume adds the chunks up.
    GLOBAL_STATE = 22,
    /// vec4 per node: the force two Chebyshev iterations back (w: its floor force).
    CHEBYSHEV_BEFORE = 23,
    /// float per spring: its damping kd_e [N s/m] (its stiffness is
    /// [`super::GpuSpring::stiffness`]; the spring force and spring_constraint passes read
    /// both, the distance pass neither).
    SPRING_DAMPING = 24,
    /// float per tet: the compliance alpha_t of its volume constraint [m^3/Pa], 0 = hard
    /// (method `volume`).
    VOLUME_COMPLIANCE = 25,
    /// float per spring: an implicit spring's multiplier lambda accumulated over the step's
    /// iterations so far (XPBD-style: `B - s lambda`; read and written only by the
    /// invocation that solves it, treated as 0 in iteration 0, so nothing resets it; with
    /// `pc.warm_start` the stored value, the last step's final one, is its multiplier so far
    /// in iteration 0).
    SPRING_MULTIPLIERS = 26,
    /// float per tet: a compliant volume constraint's multiplier so far in the step (method
    /// `volume`; hard tets leave theirs unused; like [`SPRING_MULTIPLIERS`]).
    VOLUME_MULTIPLIERS = 27,
    /// Per surface node, its body contact of the step (48 bytes, glsl/physics/bodies.glsl
    /// `BodyContactRecord`): the node and the triangle's nodes (node u32::MAX: none), the
    /// barycentric weights and the accumulated multiplier, the normal (contact_find.comp
    /// writes it, contact_solve.comp updates the multiplier).
    CONTACTS = 28,
    /// vec4 per node: the kinematic colliders' contact force so far in the step [N],
    /// re-solved with the floor's and reset to 0 by `integrate`, which leaves in w whether a
    /// collider pushed the node in its solve (1) or not (0) for `contact_measure`
    /// (glsl/physics/contact.glsl; only with colliders).
    COLLIDER_CONTACTS = 29,
    /// [`super::GpuCollider`] per collider: shape code, friction, thickness, sizes and
    /// its distance grid's placement (only with colliders).
    COLLIDERS = 30,
    /// float per sample of every mesh collider's distance grid, one grid after another
    /// (X fastest; only with colliders, 4 bytes without a mesh collider).
    COLLIDER_GRIDS = 31,
    /// [`super::GpuColliderPose`] per frame slot, substep and collider (host-visible,
    /// written before each frame's submit; `pc.collider_first` selects the substep's row;
    /// only with colliders).
    COLLIDER_POSES = 32,
    /// Body contact's surface (lavapipe allows 32 storage buffers per stage, so the static
    /// arrays share one buffer): a uvec4 per surface node ([`crate::contact::BodyContact::nodes`]:
    /// its node index, its object with bit 31 set when the object collides with itself, 0,
    /// 0), then a uvec4 per surface triangle (its three nodes, its object likewise).
    BODY_SURFACE = 33,
    /// Body contact's spatial hash, one u32 array: per bucket its count of the step
    /// (contact_count adds, contact_fill takes them back out, so 0 between steps), then per
    /// bucket + 1 the offsets of the buckets' ranges (contact_scan), then the items, triangle
    /// indices bucket after bucket (contact_fill; sized from the rest mesh with headroom, an
    /// overflow sets status flag 4).
    CONTACT_HASH = 34,
    /// vec4 per node: the body contacts' forces of the current iteration [N] (xyz, summed
    /// with float atomics by contact_solve, applied and cleared by contact_apply) and, in w
    /// (u32 bits), the node's number of body contacts this step as the node or a triangle's
    /// corner (contact_find counts with integer atomics, contact_scan clears).
    CONTACT_SUMS = 35,
    /// [`super::GpuClampNode`] per clamped node: its node, its clamp, its rest position
    /// relative to the clamp's centre (only with clamps).
    CLAMP_NODES = 36,
    /// [`super::GpuClampPose`] per frame slot, substep and clamp: the clamp's centre and
    /// rotation at the step's end (host-visible, written before each frame's submit;
    /// `pc.step_row` selects the substep's rows; only with clamps).
    CLAMP_POSES = 37,
    /// u32 per node: its row among the nodes some grab holds (u32::MAX: none; with
    /// colliders or grabs, 4 bytes without grabs).
    GRAB_NODES = 38,
    /// vec4 per frame slot, substep and grabbed node: its attachment at the step's end,
    /// the target [m] and the stiffness [N/m] in w (infinite: hard, 0: not held this step)
    /// (host-visible, written before each frame's submit; `pc.grab_first` selects the
    /// step's rows; with colliders or grabs, 4 bytes without grabs).
    GRAB_TARGETS = 39,
    /// vec4 per node: split contact's velocity at the step's end [m/s] (w unused), from the
    /// velocity solve (`split_velocity`), which `integrate` keeps instead of the full
    /// solve's (only with `contact = "split"`).
    SPLIT_VELOCITIES = 40,
    /// Anderson acceleration's history (`anderson > 0`), planes of a vec4 per node: the
    /// next input `x`, the residual `f` and the iteration's forces `g`, then the `m` columns
    /// of `df`, then the `m` of `dg` (physics/anderson.rs; w unused).
    ANDERSON_HISTORY = 41,
    /// float per Anderson chunk (a workgroup of anderson_sum) and Gram term: the chunk's
    /// share of each product of the normal equations (`gram_terms(m)` per chunk).
    ANDERSON_SUMS = 42,
    /// float per mixed multiplier (the springs', then the tets'; `anderson > 0`): the last
    /// iteration's values, then `m` planes of their differences.
    ANDERSON_MULTIPLIERS = 43,
    /// uvec4 per block of block Gauss-Seidel (volume.comp#block, one workgroup each): its
    /// first member position within the sweep, its member count, its first entry in
    /// BLOCK_NODES, its node count | colour count << 16.
    BLOCK_ROWS = 44,
    /// u32 per block node: its global node index, block after block (shared memory holds
    /// them by local index).
    BLOCK_NODES = 45,
    /// uvec4 per member position of the blocked sweep: its four corners' local indices
    /// (two 16-bit halves in x and y), its colour within its block (z), 0.
    BLOCK_CORNERS = 46,
    /// MINRES's rows' transpose, entry nodes and global rows' first entries (u32).
    MINRES_TRANSPOSE = 47,
    /// MINRES's gradient per entry (vec4).
    MINRES_GRADS = 48,
    /// MINRES's row vectors (float planes).
    MINRES_VECTORS = 49,
    /// MINRES's node vectors: the product, then the mobility (vec4 planes).
    MINRES_NODE_VECTORS = 50,
    /// MINRES's per-workgroup partial sums (float), then a count of the workgroups done.
    MINRES_SUMS = 51,
    /// MINRES's recurrence per iteration (vec4).
    MINRES_STATE = 52,
    /// [`super::GpuElasticTet`]-shaped 64 bytes per tet (finite elements): shape gradients of
    /// corners 1..3 with the rest volume, mu_s and lambda_s in w, then alpha and the damping
    /// time.
    ELASTIC_TETS = 53,
    /// Node -> tet corners CSR offsets (N + 1; finite elements).
    NODE_TET_OFFSETS = 54,
    /// Node -> tet corners CSR items (`4 tet + corner`; finite elements).
    NODE_TET_ITEMS = 55,
    /// float per coarse unknown squared, then one per unknown, then one per unknown squared
    /// (finite elements' coarse level): `P^T A P`'s columns (column-major), factored in
    /// place into `L` (the lower triangle, column-major), 1.0 per unknown kept in the
    /// factor, 0.0 per one left out (`elastic_coarse_factor`), and the inverse
    /// (`elastic_coarse_inverse`, column-major).
    COARSE_MATRIX = 56,
    /// float per coarse unknown, twice: a restricted residual, and the coarse correction
    /// (`elastic_coarse_solve`).
    COARSE_VECTOR = 57,
    /// 6 vec4 per tet (finite elements): its stiffness at the step's linearisation, F's
    /// columns and its cofactor's with the four factors in w (glsl/physics/newton.glsl,
    /// `elastic_linear_load`).
    ELASTIC_LINEAR = 58,
    /// vec4 per tet corner (`4 tet + corner`; finite elements): a product of each tet's
    /// stiffness with its corners' moves or velocities, gathered per node.
    ELASTIC_CORNERS = 59,
    /// ELASTIC_PLANES vec4 planes of one per node, plane after plane (finite elements'
    /// Newton step: where each node ends, the residual, the search direction, the inverse
    /// diagonal block, the contact's stiffening, ...; glsl/physics/newton.glsl).
    ELASTIC_NODES = 60,
    /// The finite elements' conjugate-gradient scalars, then a partial sum per workgroup
    /// of the node passes (floats; glsl/physics/newton.glsl, `ELASTIC_STATE_*`).
    ELASTIC_STATE = 61,
    /// u32 (finite elements' coarse level): the aggregates' member offsets (A + 1), their
    /// members, then each node's aggregate (0xffffffff: none).
    COARSE_AGGREGATES = 62,
    /// vec4 per aggregate (finite elements' coarse level): the centre of its nodes where the
    /// level was built, and its size (their root-mean-square distance to it).
    COARSE_MODES = 63,
    /// u32 (finite elements' coarse assembly, backend::vulkan::CoarseIndex): each tet's
    /// items, then each block's scratch rows.
    COARSE_INDEX = 64,
    /// 36 floats per item of the coarse assembly: its 6 x 6 block (row mode, column mode).
    COARSE_SCRATCH = 65,
    /// 16 words per object (finite elements' rigid-part correction): its first and end
    /// node, 1 if nothing pins it, 1 if a contact holds it; then, as floats, the rigid
    /// part's centre, acceleration and angular acceleration (vec4 each).
    ELASTIC_OBJECTS = 66,
    /// 2 vec4 per node (forces out): what holds it at the frame's last step, from
    /// `integrate`: the force on it but its pin's (a pinned node's; finite elements: but
    /// the elastic force's too) with w = the floor's normal force, then the colliders' force
    /// with w = 1 + the collider that pushes it (0: none).
    REACTION_INPUTS = 67,
    /// vec4 per reaction per `reactions` workgroup: the pins', the floor's, each collider's
    /// and each clamp's force, summed over the workgroup's nodes.
    REACTION_PARTIALS = 68,
    /// u32 per node: 1 + the clamp that holds it (0: none).
    NODE_CLAMPS = 69,
}
