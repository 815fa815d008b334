//! The buffers of one evaluation of the dynamics ([`crate::evaluation::evaluate`]), grouped
//! by the stage that computes them, each with its shape (`k = 6 n_contacts`); and the
//! evaluation's outputs ([`PlantOutputs`]), kept wherever the caller says. Declarations and
//! sizes only: the algorithms that fill them live in `evaluation.rs` (and the integrator's
//! own buffers in `integrator/`).

use crate::plant::Plant;
use crate::unilateral::PointContact;
use nalgebra::{DMatrix, DVector, Vector3};
use sea_dyn::data::Data;
use sea_dyn::tree_factor::TreeFactor;

/// Workspace of the evaluation: every intermediate buffer, by stage.
#[derive(Clone, Debug)]
pub struct Workspace {
    /// Stage 1, model terms: kinematics, bias forces `h` (in `data.tau`) and the mass matrix
    /// `M` (nv x nv) at the evaluated `q`, `nu`.
    pub data: Data,
    /// Stage 2, mass factor: the diagonal added to `M` (nv; joint inertia regularisation).
    pub(crate) diagonal: Vec<f64>,
    /// Stage 2, mass factor: `M + diag = L^T L` with the tree's sparsity.
    pub(crate) mass_factor: TreeFactor,
    /// Stage 3, contact terms (empty without contacts; under unilateral contacts only the
    /// Jacobian is used).
    pub(crate) contact: ContactTerms,
    /// Stage 3, unilateral contacts and joint stops: their linearisation, which the implicit
    /// step's `W` takes.
    pub(crate) compliance: ComplianceTerms,
    /// Stage 4, accelerations (nv): `B tau - h`, then `L^-T (B tau - h)`, then `nudot`.
    pub(crate) acceleration: DVector<f64>,
    /// Terms handed over by another user of the same model (`adopt_model_terms`).
    pub(crate) adopted: Adopted,
    /// External wrenches on links, added as `J^T w` to the dynamics while active (empty by
    /// default; the caller adds them once and switches them per step).
    pub external: Vec<crate::external::ExternalWrench>,
}

/// Stage 3 of the evaluation: the contact Jacobian and the Schur complement.
#[derive(Clone, Debug)]
pub(crate) struct ContactTerms {
    /// Stacked contact Jacobian `J` (k x nv).
    pub(crate) jacobian: DMatrix<f64>,
    /// `Y^T = (L^-T J^T)^T` with `M = L^T L` (k x nv: one contiguous k-column per velocity).
    pub(crate) linv_jt_t: DMatrix<f64>,
    /// `J M^-1 J^T`, then its Cholesky factor (k x k).
    pub(crate) schur: DMatrix<f64>,
    /// Constraint acceleration target, then the multipliers (k).
    pub(crate) target: DVector<f64>,
}

/// Stage 3 under unilateral contacts and joint stops: `-d (force) / d (pose, velocity)` at the
/// evaluated state.
#[derive(Clone, Debug)]
pub(crate) struct ComplianceTerms {
    /// Per contact point (all feet's, in order), its contact at the evaluated state: force
    /// and the slopes of its law. The feet's 6 x 6 stiffness and damping follow from these
    /// only when the implicit step prepares `W` ([`crate::compliant_forces::foot_matrices`]).
    pub(crate) points: Vec<PointContact>,
    /// Per contact point, its offset from its sole's origin (world axes) [m].
    pub(crate) point_offsets: Vec<Vector3<f64>>,
    /// Per joint, the stop's stiffness (n; 0 off its stop).
    pub(crate) stop_stiffness: Vec<f64>,
    /// Per joint, the stop's damping (n).
    pub(crate) stop_damping: Vec<f64>,
}

/// Model (and contact) terms adopted from another user of the model, waiting for the next
/// evaluation at exactly the state they were computed at.
#[derive(Clone, Debug)]
pub(crate) struct Adopted {
    /// `[q; nu]` (nq + nv) of the adopted terms.
    pub(crate) state: Vec<f64>,
    /// Whether `data`'s model terms are adopted and still unused.
    pub(crate) model: bool,
    /// Whether the mass factor and the contact terms (stage 2, 3) are adopted too.
    pub(crate) contacts: bool,
    /// `Jdot nu` of the adopted contact terms (k).
    pub(crate) jdot_nu: DVector<f64>,
}

impl Workspace {
    /// Buffers for `plant`.
    pub fn new(plant: &Plant) -> Self {
        let layout = plant.layout();
        let nv = layout.nv;
        let k = 6 * plant.contacts.len();
        Self {
            data: Data::new(&plant.model),
            diagonal: vec![0.0; nv],
            mass_factor: TreeFactor::new(&plant.model),
            contact: ContactTerms {
                jacobian: DMatrix::zeros(k, nv),
                linv_jt_t: DMatrix::zeros(k, nv),
                schur: DMatrix::zeros(k, k),
                target: DVector::zeros(k),
            },
            compliance: ComplianceTerms {
                points: vec![PointContact::default(); plant.n_contact_points()],
                point_offsets: vec![Vector3::zeros(); plant.n_contact_points()],
                stop_stiffness: vec![0.0; plant.model.n_joints()],
                stop_damping: vec![0.0; plant.model.n_joints()],
            },
            acceleration: DVector::zeros(nv),
            adopted: Adopted {
                state: vec![0.0; layout.nq + nv],
                model: false,
                contacts: false,
                jdot_nu: DVector::zeros(k),
            },
            external: Vec::new(),
        }
    }
}

/// The outputs of one evaluation: the tangent derivative and what the plant reports at the
/// evaluated state. [`crate::evaluation::evaluate`] writes them where its caller says (the
/// integrator: the step-start evaluation into the caller's outputs, later stages into its own).
#[derive(Clone, Debug, PartialEq)]
pub struct PlantOutputs {
    /// Tangent derivative `[nu; thetadot; nudot; thetaddot]` (nd; blocks:
    /// [`sea_dyn::TangentLayout`]).
    pub xdot: DVector<f64>,
    /// Contact wrenches `[f; n]` per contact at the frame origins, world axes (k).
    pub contact_wrench: DVector<f64>,
    /// Joint torques applied to the links (n): spring-damper torque or rigid input.
    pub joint_torque: DVector<f64>,
    /// Motor torques after saturation (n_e), motor side.
    pub motor_torque: DVector<f64>,
    /// Whether each motor torque hit its limit (n_e).
    pub saturated: Vec<bool>,
    /// After a step under unilateral contacts: the contact wrenches the step delivered (6 per
    /// contact, as `contact_wrench`), its effective average over the step: each stage's
    /// wrench with the implicit step's response of the stiff contact terms, weighted as the
    /// method combines its stages. A stiff contact's force follows a new input within a step,
    /// so the wrench at the step's start alone does not say what the step delivered. After a
    /// plain evaluation (and under bilateral contacts), `contact_wrench`.
    pub step_contact_wrench: DVector<f64>,
    /// Unilateral contacts: each point's force on its foot, world axes (3 per point, contacts
    /// in order, points in the order given; empty under bilateral contacts).
    pub contact_point_force: DVector<f64>,
    /// Unilateral contacts: each point's position, world (3 per point).
    pub contact_point_position: DVector<f64>,
    /// Unilateral contacts: whether each point carries a force (one per point).
    pub contact_point_active: Vec<bool>,
    /// Joint stops: the torque each joint's stop applies (n; zeros without stops).
    pub joint_stop_torque: DVector<f64>,
    /// Joint stops: whether each joint rests on a stop (n).
    pub joint_stop_active: Vec<bool>,
    /// Largest contact position error [m] (bilateral contacts).
    pub drift_position: f64,
    /// Largest contact rotation error [rad] (bilateral contacts).
    pub drift_rotation: f64,
}

impl PlantOutputs {
    /// Zeroed outputs sized for `plant`.
    pub fn new(plant: &Plant) -> Self {
        let layout = plant.layout();
        let ne = layout.ne;
        Self {
            xdot: DVector::zeros(layout.nd()),
            contact_wrench: DVector::zeros(6 * plant.contacts.len()),
            joint_torque: DVector::zeros(plant.model.n_joints()),
            motor_torque: DVector::zeros(ne),
            saturated: vec![false; ne],
            step_contact_wrench: DVector::zeros(6 * plant.contacts.len()),
            contact_point_force: DVector::zeros(3 * plant.n_contact_points()),
            contact_point_position: DVector::zeros(3 * plant.n_contact_points()),
            contact_point_active: vec![false; plant.n_contact_points()],
            joint_stop_torque: DVector::zeros(plant.model.n_joints()),
            joint_stop_active: vec![false; plant.model.n_joints()],
            drift_position: 0.0,
            drift_rotation: 0.0,
        }
    }

    /// Copies `other` (outputs of the same plant) into `self`; allocates nothing.
    pub fn copy_from(&mut self, other: &PlantOutputs) {
        let vectors = [
            (&mut self.xdot, &other.xdot),
            (&mut self.contact_wrench, &other.contact_wrench),
            (&mut self.step_contact_wrench, &other.step_contact_wrench),
            (&mut self.joint_torque, &other.joint_torque),
            (&mut self.motor_torque, &other.motor_torque),
            (&mut self.contact_point_force, &other.contact_point_force),
            (
                &mut self.contact_point_position,
                &other.contact_point_position,
            ),
            (&mut self.joint_stop_torque, &other.joint_stop_torque),
        ];
        for (target, source) in vectors {
            target.as_mut_slice().copy_from_slice(source.as_slice());
        }
        self.saturated.copy_from_slice(&other.saturated);
        self.contact_point_active
            .copy_from_slice(&other.contact_point_active);
        self.joint_stop_active
            .copy_from_slice(&other.joint_stop_active);
        self.drift_position = other.drift_position;
        self.drift_rotation = other.drift_rotation;
    }
}
