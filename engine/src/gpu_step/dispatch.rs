//! How many workgroups a dispatch over a buffer of particles takes, and
//! the device limits that bound it (shared by the step and the row kernels).

use super::error::GpuStepError;

/// Invocations a workgroup (`@workgroup_size` in `step.wgsl`).
pub const WORKGROUP: u32 = 256;

/// The particle count as the shader's `n`, and the workgroups of one
/// dispatch `(x, y)` (past the per-dimension limit, the rest folds into
/// y), or the limit the particles are past, in a buffer of `records`
/// vec4s a particle (the largest the step binds: a method's history, the
/// n-body rounds).
pub(super) fn dispatch(count: usize, records: u32, limits: &wgpu::Limits) -> Result<(u32, (u32, u32)), GpuStepError> {
    let record = 16 * u64::from(records.max(1));
    let bytes = (count as u64).saturating_mul(record);
    for (limit, value) in [
        (
            "max_storage_buffer_binding_size",
            limits.max_storage_buffer_binding_size,
        ),
        ("max_buffer_size", limits.max_buffer_size),
    ] {
        if bytes > value {
            return Err(GpuStepError::Limit {
                limit,
                value,
                needed: bytes,
                fits: value / record,
            });
        }
    }
    let per_dimension = u64::from(limits.max_compute_workgroups_per_dimension.max(1));
    let groups = (count as u64).div_ceil(u64::from(WORKGROUP));
    let x = groups.min(per_dimension);
    let y = groups.div_ceil(x.max(1));
    let n = u32::try_from(count)
        .ok()
        .filter(|_| y <= per_dimension)
        .ok_or(GpuStepError::Limit {
            limit: "max_compute_workgroups_per_dimension",
            value: per_dimension,
            needed: y,
            fits: per_dimension * per_dimension * u64::from(WORKGROUP),
        })?;
    // Both fit in u32: x and y are at most the per-dimension limit.
    Ok((n, (x as u32, y.max(1) as u32)))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_dispatch_folds_past_the_per_dimension_limit_and_buffers_past_their_limits_are_errors() {
        let limits = wgpu::Limits {
            max_compute_workgroups_per_dimension: 65_535,
            max_storage_buffer_binding_size: 1 << 30,
            max_buffer_size: 1 << 30,
            ..wgpu::Limits::downlevel_defaults()
        };
        assert_eq!(dispatch(0, 1, &limits), Ok((0, (0, 1))));
        assert_eq!(dispatch(1000, 1, &limits), Ok((1000, (4, 1))));
        // 10 million: 39 063 workgroups, one row.
        assert_eq!(dispatch(10_000_000, 1, &limits), Ok((10_000_000, (39_063, 1))));
        // 20 million: 78 125 workgroups, two rows of 65 535.
        assert_eq!(dispatch(20_000_000, 1, &limits), Ok((20_000_000, (65_535, 2))));
        let small = wgpu::Limits {
            max_storage_buffer_binding_size: 1 << 20,
            ..limits
        };
        assert_eq!(
            dispatch(100_000, 1, &small),
            Err(GpuStepError::Limit {
                limit: "max_storage_buffer_binding_size",
                value: 1 << 20,
                needed: 1_600_000,
                fits: 65_536,
            })
        );
        assert_eq!(
            dispatch(100_000, 1, &small).map_err(|e| e.to_string()),
            Err(
                "the particles need 1600000 of the device's max_storage_buffer_binding_size (1048576): at most \
                 65536 particles fit"
                    .to_owned()
            )
        );
        // Adams-Bashforth 4's six history records a particle: a sixth fit.
        assert_eq!(
            dispatch(20_000, 6, &small),
            Err(GpuStepError::Limit {
                limit: "max_storage_buffer_binding_size",
                value: 1 << 20,
                needed: 1_920_000,
                fits: 10_922,
            })
        );
    }
}
