//! Numbers as the panels write them: thousands separators, metres, milliseconds.

/// `1234567` as `"1,234,567"`.
pub fn thousands(n: u64) -> String {
    let digits = n.to_string();
    let mut out = String::with_capacity(digits.len() + digits.len() / 3);
    for (i, c) in digits.chars().enumerate() {
        if i > 0 && (digits.len() - i).is_multiple_of(3) {
            out.push(',');
        }
        out.push(c);
    }
    out
}

/// A length in metres with as many decimals as its size deserves.
pub fn metres(v: f32) -> String {
    if v.is_finite() {
        format!("{} m", length(v))
    } else {
        "n/a".to_owned()
    }
}

/// A length without its unit, with as many decimals as its size deserves.
pub fn length(v: f32) -> String {
    if !v.is_finite() {
        return "n/a".to_owned();
    }
    let a = v.abs();
    let decimals = if a >= 100.0 {
        0
    } else if a >= 10.0 {
        1
    } else if a >= 1.0 {
        2
    } else if a >= 0.01 || a == 0.0 {
        3
    } else {
        4
    };
    format!("{v:.decimals$}")
}

/// A time in milliseconds.
pub fn millis(ms: f64) -> String {
    if ms < 10.0 {
        format!("{ms:.2} ms")
    } else {
        format!("{ms:.1} ms")
    }
}

/// `[x, y, z]` as `"(x, y, z)"` with two decimals (no unit).
pub fn point(p: [f32; 3]) -> String {
    format!("({:.2}, {:.2}, {:.2})", p[0], p[1], p[2])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn thousands_groups_by_three() {
        assert_eq!(thousands(0), "0");
        assert_eq!(thousands(999), "999");
        assert_eq!(thousands(1000), "1,000");
        assert_eq!(thousands(1_234_567), "1,234,567");
        assert_eq!(thousands(u64::MAX), "18,446,744,073,709,551,615");
    }

    #[test]
    fn metres_picks_decimals_by_size() {
        assert_eq!(metres(123.4), "123 m");
        assert_eq!(metres(12.34), "12.3 m");
        assert_eq!(metres(1.234), "1.23 m");
        assert_eq!(metres(0.0488), "0.049 m");
        assert_eq!(metres(0.0012), "0.0012 m");
        assert_eq!(metres(0.0), "0.000 m");
        assert_eq!(metres(f32::NAN), "n/a");
        assert_eq!(length(f32::INFINITY), "n/a");
        assert_eq!(length(-2.5), "-2.50");
    }

    #[test]
    fn millis_keeps_two_significant_decimals_for_small_times() {
        assert_eq!(millis(1.234), "1.23 ms");
        assert_eq!(millis(16.66), "16.7 ms");
    }
}
