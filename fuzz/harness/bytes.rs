//! The program decoder and the value generators: `Bytes` reads integers from the input (zeros
//! past its end) and turns them into awkward floats, step sizes, quaternions and plausible
//! parameter values. Uses std only; knows nothing of FMI.

/// The program bytes; reads past the end yield zeros.
pub struct Bytes<'a> {
    d: &'a [u8],
    i: usize,
}

impl<'a> Bytes<'a> {
    pub fn new(d: &'a [u8]) -> Self {
        Bytes { d, i: 0 }
    }
    pub(super) fn done(&self) -> bool {
        self.i >= self.d.len()
    }
    pub(super) fn u8(&mut self) -> u8 {
        let b = self.d.get(self.i).copied().unwrap_or(0);
        self.i += 1;
        b
    }
    pub(super) fn u16(&mut self) -> u16 {
        u16::from_le_bytes([self.u8(), self.u8()])
    }
    pub(super) fn u32(&mut self) -> u32 {
        u32::from_le_bytes([self.u8(), self.u8(), self.u8(), self.u8()])
    }
    fn u64(&mut self) -> u64 {
        (self.u32() as u64) | ((self.u32() as u64) << 32)
    }
    /// A signed value in [−1, 1).
    pub(super) fn unit(&mut self) -> f64 {
        (self.u16() as i16) as f64 / 32768.0
    }

    /// A float from the pool of awkward and ordinary values.
    pub(super) fn real(&mut self) -> f64 {
        match self.u8() % 24 {
            0 => f64::NAN,
            1 => f64::INFINITY,
            2 => f64::NEG_INFINITY,
            3 => 1e308,
            4 => -1e308,
            5 => 5e-324,
            6 => -0.0,
            7 => 0.0,
            8 => 1.0,
            9 => -1.0,
            10 => f64::MAX,
            11 => f64::MIN_POSITIVE,
            12 => f64::from_bits(self.u64()),
            13 => std::f64::consts::PI * (self.u8() as i8) as f64 / 16.0,
            14 => 1e-12 * self.unit(),
            15 => 1e6 * self.unit(),
            16 => -5e-324,
            17 => 1e154 * self.unit(),
            _ => 10.0 * self.unit(),
        }
    }

    /// A step size: zero, negative, non-finite, huge, denormal, ordinary.
    pub(super) fn step(&mut self) -> f64 {
        match self.u8() % 16 {
            0 => 0.0,
            1 => -1e-3,
            2 => f64::NAN,
            3 => f64::INFINITY,
            4 => 1e300,
            5 => 5e-324,
            6 => 1.0,
            7 => 1e-6,
            8 => 0.1 * (1.0 + self.unit()),
            9 => self.real(),
            _ => 1e-3 * (1.0 + 4.0 * (self.u8() as f64 / 255.0)),
        }
    }

    /// Four quaternion components (w, x, y, z).
    pub(super) fn quat(&mut self) -> [f64; 4] {
        let axis_angle = |b: &mut Self, angle: f64| {
            let mut ax = [b.unit(), b.unit(), b.unit()];
            let n = (ax[0] * ax[0] + ax[1] * ax[1] + ax[2] * ax[2]).sqrt();
            if n < 1e-3 {
                ax = [1.0, 0.0, 0.0];
            } else {
                ax.iter_mut().for_each(|x| *x /= n);
            }
            let (s, c) = (angle / 2.0).sin_cos();
            [c, s * ax[0], s * ax[1], s * ax[2]]
        };
        let about_x = |angle: f64| {
            let (s, c) = (angle / 2.0).sin_cos();
            [c, s, 0.0, 0.0]
        };
        let pi = std::f64::consts::PI;
        match self.u8() % 16 {
            0 => [0.0; 4],
            1 => [1e-7, 0.0, 0.0, 0.0],
            2 => [1e200, 0.0, 0.0, 1e200],
            3 => [f64::NAN, 0.0, 0.0, 1.0],
            4 => [1.0, f64::INFINITY, 0.0, 0.0],
            5 => [5e-324, 5e-324, 0.0, 0.0],
            6 => [self.real(), self.real(), self.real(), self.real()],
            7 => about_x(pi),
            8 => about_x(pi - 1e-3 * self.u8() as f64 / 128.0),
            9 => {
                let s = 1e-6 * (1.0 + self.unit());
                let q = about_x(self.unit() * pi);
                q.map(|x| x * s)
            }
            10 => {
                let s = 1e150;
                about_x(self.unit() * pi).map(|x| x * s)
            }
            _ => {
                let angle = pi * self.unit() * (1 + self.u8() % 2) as f64;
                axis_angle(self, angle)
            }
        }
    }

    /// A plausible parameter value for a parameter named `name`.
    pub(super) fn param_value(&mut self, name: &str) -> f64 {
        if self.u8().is_multiple_of(8) {
            return self.real();
        }
        let u = self.unit();
        if name.starts_with("stop.lower") {
            -0.2 * u.abs()
        } else if name.starts_with("stop.upper") {
            0.2 * u.abs()
        } else if name.starts_with("reference.value") || name.ends_with("int") {
            u
        } else if name.contains("mu") {
            u.abs()
        } else if name.contains("R") && name.starts_with("friction.") && !name.contains("R1") {
            0.05 * u.abs()
        } else {
            10f64.powf(6.0 * u.abs()) - 1.0
        }
    }
}
