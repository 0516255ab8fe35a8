//! Where the view frustum is cut into cascades: the split schemes of Engel (a geometric
//! progression of far distances, "doubled or tripled each time"), Zhang et al.'s parallel-split
//! shadow maps (uniform, logarithmic and their blend, the "practical" scheme with weight
//! lambda) and distances the user gives. Pure functions of the depth range the cascades cover.

use serde::{Deserialize, Serialize};

/// How the depth range `[near, far]` is cut.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum SplitScheme {
    /// Equal depth ranges: `near + (far - near) i / n`.
    Uniform,
    /// Equal ratios: `near (far / near)^(i / n)`, the ideal for a perspective view (Lloyd).
    Logarithmic,
    /// Zhang's blend: `lambda` of the logarithmic split plus `1 - lambda` of the uniform one.
    #[default]
    Practical,
    /// Engel: the first cascade ends at `first_m`, each next far distance is `ratio` times the
    /// one before (10, 30, 90, 270 m for 10 m and 3).
    Geometric,
    /// The inner distances the user gives, in metres.
    Manual,
}

impl SplitScheme {
    pub const ALL: [Self; 5] = [
        Self::Uniform,
        Self::Logarithmic,
        Self::Practical,
        Self::Geometric,
        Self::Manual,
    ];

    pub fn name(self) -> &'static str {
        match self {
            Self::Uniform => "uniform",
            Self::Logarithmic => "logarithmic",
            Self::Practical => "practical",
            Self::Geometric => "geometric",
            Self::Manual => "manual",
        }
    }
}

impl std::str::FromStr for SplitScheme {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        Self::ALL
            .into_iter()
            .find(|scheme| scheme.name() == s)
            .ok_or_else(|| {
                let names: Vec<_> = Self::ALL.iter().map(|s| s.name()).collect();
                format!(
                    "unknown split scheme '{s}' (available: {})",
                    names.join(", ")
                )
            })
    }
}

/// The parameters of every scheme; each scheme reads its own.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct Splits {
    pub scheme: SplitScheme,
    /// Practical: the logarithmic share, 0 (uniform) to 1 (logarithmic).
    pub lambda: f32,
    /// Geometric: where the first cascade ends, and the factor from one far distance to the
    /// next.
    pub first_m: f32,
    pub ratio: f32,
    /// Manual: the distances between cascades, increasing (one fewer than cascades; one that
    /// is not above 0 is filled in uniformly).
    pub manual_m: [f32; 7],
}

impl Default for Splits {
    fn default() -> Self {
        Self {
            scheme: SplitScheme::Practical,
            lambda: 0.75,
            first_m: 10.0,
            ratio: 3.0,
            manual_m: [0.0; 7],
        }
    }
}

impl Splits {
    /// The `count + 1` distances from `near` to `far` that bound `count` cascades, increasing.
    /// Geometric far distances past `far` stop at it; one that ends before `far` leaves the
    /// depths beyond it to no cascade (Engel's shadow distance). Degenerate inputs give a
    /// finite, non-decreasing answer.
    pub fn distances(&self, count: u32, near: f64, far: f64) -> Vec<f64> {
        let count = count.max(1);
        let near = if near.is_finite() && near > 0.0 {
            near
        } else {
            1e-3
        };
        let far = if far.is_finite() && far > near {
            far
        } else {
            near * 2.0
        };
        let n = f64::from(count);
        let uniform = |i: f64| near + (far - near) * i / n;
        let logarithmic = |i: f64| near * (far / near).powf(i / n);
        let mut out: Vec<f64> = (0..=count)
            .map(|i| {
                let i = f64::from(i);
                match self.scheme {
                    SplitScheme::Uniform => uniform(i),
                    SplitScheme::Logarithmic => logarithmic(i),
                    SplitScheme::Practical => {
                        let lambda = f64::from(self.lambda.clamp(0.0, 1.0));
                        lambda * logarithmic(i) + (1.0 - lambda) * uniform(i)
                    }
                    SplitScheme::Geometric => {
                        let first = f64::from(self.first_m).max(near);
                        let ratio = f64::from(self.ratio).max(1.0);
                        if i == 0.0 {
                            near
                        } else {
                            first * ratio.powf(i - 1.0)
                        }
                    }
                    SplitScheme::Manual => (i > 0.0 && i < n)
                        .then(|| self.manual_m.get(i as usize - 1))
                        .flatten()
                        .filter(|d| d.is_nan() || **d > 0.0)
                        .map_or_else(|| uniform(i), |&d| f64::from(d)),
                }
            })
            .collect();
        // The ends are exact; the rest stays within them and never decreases.
        out[0] = near;
        if self.scheme != SplitScheme::Geometric {
            out[count as usize] = far;
        }
        let mut previous = near;
        for d in &mut out {
            *d = if d.is_finite() {
                d.clamp(previous, far)
            } else {
                previous
            };
            previous = *d;
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn splits(scheme: SplitScheme) -> Splits {
        Splits {
            scheme,
            ..Splits::default()
        }
    }

    fn assert_close(got: &[f64], want: &[f64]) {
        assert_eq!(got.len(), want.len(), "{got:?} against {want:?}");
        for (g, w) in got.iter().zip(want) {
            assert!(
                (g - w).abs() <= 1e-9 * w.abs().max(1.0),
                "{got:?} against {want:?}"
            );
        }
    }

    #[test]
    fn each_scheme_equals_its_closed_form() {
        let (near, far) = (1.0, 1000.0);
        assert_close(
            &splits(SplitScheme::Uniform).distances(4, near, far),
            &[1.0, 250.75, 500.5, 750.25, 1000.0],
        );
        // 1000^(i/3): 1, 10, 100, 1000.
        assert_close(
            &splits(SplitScheme::Logarithmic).distances(3, near, far),
            &[1.0, 10.0, 100.0, 1000.0],
        );
        // lambda 0.5 of (10, 100) and of (334, 667).
        let practical = Splits {
            lambda: 0.5,
            ..splits(SplitScheme::Practical)
        };
        assert_close(
            &practical.distances(3, near, far),
            &[
                1.0,
                0.5 * 10.0 + 0.5 * 334.0,
                0.5 * 100.0 + 0.5 * 667.0,
                1000.0,
            ],
        );
        // Engel's example: 10, 30, 90, 270 m.
        assert_close(
            &splits(SplitScheme::Geometric).distances(4, 0.1, 1000.0),
            &[0.1, 10.0, 30.0, 90.0, 270.0],
        );
        let manual = Splits {
            manual_m: [5.0, 50.0, 0.0, 0.0, 0.0, 0.0, 0.0],
            ..splits(SplitScheme::Manual)
        };
        assert_close(&manual.distances(3, near, far), &[1.0, 5.0, 50.0, 1000.0]);
    }

    #[test]
    fn lambda_ends_are_the_pure_schemes() {
        let (near, far) = (0.5, 3000.0);
        for (lambda, pure) in [(0.0, SplitScheme::Uniform), (1.0, SplitScheme::Logarithmic)] {
            let practical = Splits {
                lambda,
                ..splits(SplitScheme::Practical)
            };
            assert_close(
                &practical.distances(5, near, far),
                &splits(pure).distances(5, near, far),
            );
        }
    }

    #[test]
    fn out_of_range_and_degenerate_inputs_stay_ordered_and_finite() {
        // A geometric progression past the far distance stops there.
        assert_close(
            &splits(SplitScheme::Geometric).distances(4, 0.1, 50.0),
            &[0.1, 10.0, 30.0, 50.0, 50.0],
        );
        // Manual distances out of order or out of range are clamped into order.
        let manual = Splits {
            manual_m: [800.0, 20.0, f32::NAN, 0.0, 0.0, 0.0, 0.0],
            ..splits(SplitScheme::Manual)
        };
        let d = manual.distances(4, 1.0, 100.0);
        assert_close(&d, &[1.0, 100.0, 100.0, 100.0, 100.0]);
        for scheme in SplitScheme::ALL {
            for (near, far) in [
                (0.0, 0.0),
                (f64::NAN, 10.0),
                (1.0, f64::INFINITY),
                (0.01, 1e4),
            ] {
                let d = splits(scheme).distances(8, near, far);
                assert_eq!(d.len(), 9);
                assert!(d.iter().all(|x| x.is_finite()), "{scheme:?} {d:?}");
                assert!(d.windows(2).all(|w| w[0] <= w[1]), "{scheme:?} {d:?}");
            }
        }
    }

    #[test]
    fn names_parse_back() {
        for scheme in SplitScheme::ALL {
            assert_eq!(scheme.name().parse::<SplitScheme>(), Ok(scheme));
        }
        assert!(
            "zhang"
                .parse::<SplitScheme>()
                .unwrap_err()
                .contains("practical")
        );
    }
}
