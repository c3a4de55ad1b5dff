//! Wide integer arithmetic for the clock's exact time: `a * m / d` rounded,
//! through a 256-bit product, because the units of a rate from
//! [`Rate::hz_f64`](super::Rate::hz_f64) pass 2^64 and their products pass
//! `u128`. Run only when the rate changes.

/// `a * m / d` for `d > 0`, rounded to nearest (halves up), exact for any
/// `u128` operands (the result saturates only past `u128`). The units of
/// a rate from [`Rate::hz_f64`] pass 2^64 (a step's denominator reaches
/// about 1e12, times 1e9 units a second), so `rest * m` needs 256 bits.
pub(super) fn mul_div_round(a: u128, m: u128, d: u128) -> u128 {
    let (whole, rest) = (a / d, a % d);
    // rest < d, so rest * m / d < m fits; only the product is wide.
    whole
        .saturating_mul(m)
        .saturating_add(wide_div_round(widening_mul(rest, m), d))
}

/// The 256-bit product `a * b`, as its `(high, low)` 128-bit halves.
fn widening_mul(a: u128, b: u128) -> (u128, u128) {
    const LOW: u128 = u64::MAX as u128;
    let (a1, a0) = (a >> 64, a & LOW);
    let (b1, b0) = (b >> 64, b & LOW);
    let (p00, p01, p10, p11) = (a0 * b0, a0 * b1, a1 * b0, a1 * b1);
    // Below 3 * 2^64: no overflow.
    let middle = (p00 >> 64) + (p01 & LOW) + (p10 & LOW);
    let low = (p00 & LOW) | (middle << 64);
    let high = p11 + (p01 >> 64) + (p10 >> 64) + (middle >> 64);
    (high, low)
}

/// `(n + d / 2) / d` for a 256-bit `n = (high, low)` below `d * (2^128 - 1)`
/// (so the quotient fits `u128`): binary long division, 128 rounds, run
/// only when the rate changes.
fn wide_div_round((high, low): (u128, u128), d: u128) -> u128 {
    let (low, carry) = low.overflowing_add(d / 2);
    // n + d/2 < d * 2^128, so the high half stays below d.
    let mut remainder = high + u128::from(carry);
    let mut quotient = 0u128;
    for bit in (0..128).rev() {
        // remainder < d; doubling it may pass 2^128 (`overflow`), and then
        // it is surely at least d, and the difference fits again.
        let overflow = remainder >> 127 == 1;
        remainder = (remainder << 1) | ((low >> bit) & 1);
        quotient <<= 1;
        if overflow || remainder >= d {
            remainder = remainder.wrapping_sub(d);
            quotient |= 1;
        }
    }
    quotient
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mul_div_round_is_exact_past_u128_products() {
        // Small values against plain arithmetic.
        for (a, m, d) in [(7u128, 3u128, 2u128), (10, 10, 3), (1, 1, 2), (5, 0, 7), (0, 9, 4)] {
            assert_eq!(mul_div_round(a, m, d), (a * m + d / 2) / d, "{a} * {m} / {d}");
        }
        // (2^128 - 1)^2 = 2^256 - 2^129 + 1.
        assert_eq!(widening_mul(u128::MAX, u128::MAX), (u128::MAX - 1, 1));
        // Products far past u128: the quotient q satisfies
        // q d <= a m + d/2 < (q + 1) d, checked in 256 bits.
        let cases = [
            (10u128.pow(21) - 7, 10u128.pow(21) + 3, 10u128.pow(21) + 1),
            (u128::MAX / 3, u128::MAX / 5, u128::MAX / 4),
            (
                123_456_789_012_345_678_901_234,
                987_654_321_098_765_432_109,
                555_555_555_555_555_555_555_557,
            ),
        ];
        for (a, m, d) in cases {
            let rest = a % d;
            let q = mul_div_round(rest, m, d);
            let (high, low) = widening_mul(rest, m);
            let (low, carry) = low.overflowing_add(d / 2);
            let n = (high + u128::from(carry), low);
            let below = widening_mul(q, d);
            let above = {
                let (h, l) = widening_mul(q, d);
                let (l, c) = l.overflowing_add(d);
                (h + u128::from(c), l)
            };
            assert!(below <= n && n < above, "{rest} * {m} / {d} gave {q}");
        }
    }
}
