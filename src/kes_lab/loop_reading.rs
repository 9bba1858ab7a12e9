//! Reading a KES loop the way the instrument's software does: rigidities as the mean slope of the
//! branches over a range, hysteresis as the mean loop width at ±x.

use super::strip::Reading;

/// One swept cycle: legs 0 → +max (first loading), +max → −max (falling branch), −max → +max
/// (rising branch).
#[derive(Clone, Debug, PartialEq)]
pub struct KesLoop {
    /// The three legs, in sweep order.
    pub legs: [Vec<Reading>; 3],
}

impl KesLoop {
    /// y on `leg` at `x` (linear between sweep points; legs are monotone in x).
    fn at(leg: &[Reading], x: f64) -> f64 {
        let ascending = leg.last().map(|r| r.x) > leg.first().map(|r| r.x);
        let after = leg
            .iter()
            .position(|r| if ascending { r.x >= x } else { r.x <= x })
            .unwrap_or(leg.len() - 1)
            .max(1);
        let (a, b) = (leg[after - 1], leg[after]);
        if a.x == b.x {
            return b.y;
        }
        a.y + (b.y - a.y) * (x - a.x) / (b.x - a.x)
    }

    /// The rising (last leg) and falling (middle leg) branch values at `x`.
    pub fn branches(&self, x: f64) -> (f64, f64) {
        (Self::at(&self.legs[2], x), Self::at(&self.legs[1], x))
    }

    /// ∮ y dx around the closed loop (the falling then the rising branch), y·x units: the work
    /// done on a unit of the sample per cycle, which hysteresis dissipates.
    pub fn area(&self) -> f64 {
        let integral = |leg: &[Reading]| -> f64 {
            leg.windows(2)
                .map(|w| 0.5 * (w[0].y + w[1].y) * (w[1].x - w[0].x))
                .sum()
        };
        integral(&self.legs[1]) + integral(&self.legs[2])
    }

    /// Mean slope of both branches over [a, b] and over [−b, −a] (y per x).
    pub fn rigidity(&self, a: f64, b: f64) -> f64 {
        let ((r_b, f_b), (r_a, f_a)) = (self.branches(b), self.branches(a));
        let ((r_nb, f_nb), (r_na, f_na)) = (self.branches(-b), self.branches(-a));
        let positive = (r_b - r_a) + (f_b - f_a);
        let negative = (r_na - r_nb) + (f_na - f_nb);
        (positive + negative) / (4.0 * (b - a))
    }

    /// Mean loop width (rising minus falling branch) at +x and −x (y units).
    pub fn width(&self, x: f64) -> f64 {
        let (r, f) = self.branches(x);
        let (rn, fn_) = self.branches(-x);
        0.5 * ((r - f) + (rn - fn_))
    }
}
