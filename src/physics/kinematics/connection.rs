//! The connection types (the manual's translational and rotational parts and their pairings,
//! docs/physics.md, "Kinematics") and the role of every component slot in each: what the
//! other parts of the kinematics, and the variable tables, branch on; `with_constant_type`
//! makes the type a constant in a body, one copy per packaged type. Uses nothing else of the
//! kernel.

/// Translational part of a connection type.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Translational {
    /// No translational components.
    None,
    /// PROJECTION CARTESIAN: x, y, z along the centred projection triad.
    ProjectionCartesian,
    /// SLIDE-PLANE: y, z in the plane of normal e1a (available), x = e1a·d constrained.
    SlidePlane,
    /// RADIAL-THRUST: r (component 1) and l (component 3) about the axis e3a.
    RadialThrust,
}

/// Rotational part of a connection type.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Rotational {
    /// No rotational components.
    None,
    /// PROJECTION FLEXION-TORSION: α1, α2, β on the centred triad.
    ProjectionFlexionTorsion,
    /// REVOLUTE: α about e1a (available), e1b kept along e1a by two constraint rotations.
    Revolute,
}

/// What a component slot is in a connection type.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Role {
    /// Not part of the connection type.
    Absent,
    /// An available component: constitutive behaviour, stops, friction act on it.
    Available,
    /// A kinematic constraint, enforced by a penalty; its reaction is CRF/CRM.
    Constrained,
}

/// A connection type: translational part + rotational part (or an assembled type).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ConnectionType {
    /// Translational part.
    pub trans: Translational,
    /// Rotational part.
    pub rot: Rotational,
}

/// `$body` evaluated with `$c` a constant copy of the connection type `$ct`, one copy of the
/// body per connection type of the variants (the branches on the type and its roles fold
/// away in each); other pairings take the general copy, `$c` = `$ct`.
macro_rules! with_constant_type {
    ($ct:expr, |$c:ident| $body:expr) => {
        with_constant_type!(@types $ct, $c, $body;
            (SlidePlane, Revolute),
            (ProjectionCartesian, None),
            (None, ProjectionFlexionTorsion),
            (ProjectionCartesian, ProjectionFlexionTorsion),
            (RadialThrust, None))
    };
    (@types $ct:expr, $c:ident, $body:expr; $(($t:ident, $r:ident)),*) => {{
        use $crate::physics::kinematics::{
            ConnectionType as Ct, Rotational as R, Translational as T,
        };
        let ct: Ct = $ct;
        match (ct.trans, ct.rot) {
            $((T::$t, R::$r) => {
                const $c: Ct = Ct { trans: T::$t, rot: R::$r };
                $body
            })*
            _ => {
                #[allow(non_snake_case)]
                let $c = ct;
                $body
            }
        }
    }};
}
pub(crate) use with_constant_type;

impl ConnectionType {
    /// Role of every component slot (k = 1..6 at index k−1).
    #[inline(always)]
    pub fn roles(&self) -> [Role; 6] {
        use Role::*;
        let mut r = [Absent; 6];
        match self.trans {
            Translational::None => {}
            Translational::ProjectionCartesian => r[..3].copy_from_slice(&[Available; 3]),
            Translational::SlidePlane => {
                r[..3].copy_from_slice(&[Constrained, Available, Available])
            }
            Translational::RadialThrust => {
                r[0] = Available;
                r[2] = Available;
            }
        }
        match self.rot {
            Rotational::None => {}
            Rotational::ProjectionFlexionTorsion => r[3..].copy_from_slice(&[Available; 3]),
            Rotational::Revolute => r[3..].copy_from_slice(&[Available, Constrained, Constrained]),
        }
        r
    }

    /// Whether the local directions are the centred projection triad (else they follow node a).
    pub fn centred(&self) -> bool {
        self.trans == Translational::ProjectionCartesian
            || self.rot == Rotational::ProjectionFlexionTorsion
    }

    /// Whether node a's orientation matters (else it is not an input of the FMU).
    pub fn uses_orientation_a(&self) -> bool {
        self.centred() || self.trans != Translational::None || self.rot != Rotational::None
    }

    /// Whether node b's orientation matters (RADIAL-THRUST: "orientation at b: ignored").
    pub fn uses_orientation_b(&self) -> bool {
        self.centred() || self.rot != Rotational::None
    }

    /// Whether the node positions matter.
    pub fn uses_positions(&self) -> bool {
        self.trans != Translational::None
    }
}
