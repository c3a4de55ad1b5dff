// n-body on the GPU (see "n-body" in step.wgsl): the term a method's
// evaluation reads, and the sums a round computes between probes.

// The n-body evaluation a probe writes the trial positions of; NONE in the
// step proper, which reads every evaluation's sums.
override STAGE: u32 = 4294967295u;
const NONE: u32 = 4294967295u;
// The particle's n-body evaluations so far in this pass.
var<private> call: u32;

// The n-body term of this evaluation at `x`: its sum if known; in the
// probe of this evaluation, `x` is written down for the sums.
fn nbody_term(x: vec3<f32>) -> vec3<f32> {
    let k = call;
    call = call + 1u;
    if (k < STAGE) {
        return nbody[k * params.n + row].xyz;
    }
    if (k == STAGE) {
        nbody[STAGES * params.n + row] = vec4<f32>(x, 0.0);
        atomicMax(&flags[3], STAGE + 1u);
    }
    return vec3<f32>(0.0);
}

// The n-body sums of the tile loaded into workgroup memory: positions and
// masses (1 / w, 0 for an immovable particle).
var<workgroup> tile: array<vec4<f32>, 256>;
// How many evaluations' trial positions the probes wrote (read once for
// the workgroup, so that its barriers stay uniform).
var<workgroup> reached: u32;

// Each particle's n-body acceleration of evaluation STAGE at the trial
// positions the probe wrote: every other particle in row order, 256 at a
// time through workgroup memory, summed as the CPU's `NBody::row` sums
// them (then times G).
@compute @workgroup_size(256)
fn nbody_sums(
    @builtin(global_invocation_id) id: vec3<u32>,
    @builtin(local_invocation_index) lane: u32,
) {
    if (lane == 0u) {
        reached = atomicLoad(&flags[3]);
    }
    if (workgroupUniformLoad(&reached) <= STAGE) {
        // No particle made this evaluation in this step.
        return;
    }
    let i = id.x + id.y * params.groups_x * 256u;
    let n = params.n;
    let trials = STAGES * n;
    let xi = nbody[trials + min(i, n - 1u)].xyz;
    var sum = vec3<f32>(0.0);
    for (var base = 0u; base < n; base += 256u) {
        let j = base + lane;
        if (j < n) {
            let w = velocities[j].w;
            tile[lane] = vec4<f32>(nbody[trials + j].xyz, select(0.0, 1.0 / w, w > 0.0));
        }
        workgroupBarrier();
        let count = min(256u, n - base);
        for (var k = 0u; k < count; k++) {
            let d = tile[k].xyz - xi;
            let r2 = length_squared(d) + params.nbody_eps2;
            let m = select(tile[k].w, 0.0, base + k == i);
            if (r2 > 0.0) {
                sum = sum + d * (m / (r2 * sqrt(r2)));
            }
        }
        workgroupBarrier();
    }
    if (i < n) {
        nbody[STAGE * n + i] = vec4<f32>(sum * params.nbody_g, 0.0);
    }
}
