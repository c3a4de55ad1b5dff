// A GPU world's rows following its CPU world's: the rows a step removed
// (expiry, despawns) and added (emitters, spawns), planned on the CPU from
// the world's swap-removes and applied here after the step, so the GPU's
// row order is the CPU's.
//
//   relocate:  row dst <- row src, for each move      (a surviving row from the end
//                                                      into a removed one's place)
//   place:     row dst <- the new particle's record   (after every move)
//
// No move reads a row that another writes (the CPU's swap-remove only
// moves rows down, into rows no move reads), so each dispatch is one
// independent copy an invocation, the same bits whatever their order.

struct Rows {
    moves: u32,
    spawns: u32,
    // Workgroups along x of each dispatch (past 65 535 they fold into y).
    moves_groups_x: u32,
    spawns_groups_x: u32,
    // 1 where the method keeps a history (the `history` buffer a particle).
    history: u32,
    pad0: u32,
    pad1: u32,
    pad2: u32,
}

struct Spawn {
    position: vec4<f32>,
    velocity: vec4<f32>,
    previous: vec4<f32>,
    colour: u32,
    row: u32,
    pad0: u32,
    pad1: u32,
}

@group(0) @binding(0) var<uniform> rows: Rows;
@group(0) @binding(1) var<storage, read_write> positions: array<vec4<f32>>;
@group(0) @binding(2) var<storage, read_write> velocities: array<vec4<f32>>;
@group(0) @binding(3) var<storage, read_write> previous: array<vec4<f32>>;
@group(0) @binding(4) var<storage, read_write> colours: array<u32>;
// (dst, src) a move.
@group(0) @binding(5) var<storage, read> moves: array<vec2<u32>>;
@group(0) @binding(6) var<storage, read> spawns: array<Spawn>;
// The method's history, `rows.history` records a particle (0 for a method
// without: then it is left alone).
@group(0) @binding(7) var<storage, read_write> history: array<vec4<f32>>;

@compute @workgroup_size(256)
fn relocate(@builtin(global_invocation_id) id: vec3<u32>) {
    let k = id.x + id.y * rows.moves_groups_x * 256u;
    if (k >= rows.moves) {
        return;
    }
    let m = moves[k];
    positions[m.x] = positions[m.y];
    velocities[m.x] = velocities[m.y];
    previous[m.x] = previous[m.y];
    colours[m.x] = colours[m.y];
    for (var k = 0u; k < rows.history; k++) {
        history[m.x * rows.history + k] = history[m.y * rows.history + k];
    }
}

@compute @workgroup_size(256)
fn place(@builtin(global_invocation_id) id: vec3<u32>) {
    let k = id.x + id.y * rows.spawns_groups_x * 256u;
    if (k >= rows.spawns) {
        return;
    }
    let s = spawns[k];
    positions[s.row] = s.position;
    velocities[s.row] = s.velocity;
    previous[s.row] = s.previous;
    colours[s.row] = s.colour;
    // A new particle has no history.
    for (var k = 0u; k < rows.history; k++) {
        history[s.row * rows.history + k] = vec4<f32>(0.0);
    }
}
