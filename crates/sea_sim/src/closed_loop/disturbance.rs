//! `controller.external_wrench = "generalized"` in the loop: the generalized disturbance
//! observer (`sea_ctrl::generalized_disturbance`) with what the robot's sensors read at each
//! sample, and the estimate handed to the controller.
//!
//! At sample `k`, after the period that starts there has taken its first plant step: the
//! measured state (the encoders), the joint torques as the robot senses them (an elastic
//! joint's deflection through the loop's stiffness and damping estimates, a rigid joint's
//! motor torque) and the feet's wrenches, at the start of that period (`g_k^+`) and at the end
//! of the period before (`g_k^-`: the plant's wrenches and rigid torques at the start of its
//! last step; the elastic torques, a function of the state, from the measurement at `k`).

use nalgebra::DVector;
use sea_ctrl::generalized_disturbance::{AppliedForces, GeneralizedDisturbanceObserver};
use sea_ctrl::MomentumController;
use sea_dyn::{ElasticParameters, StateLayout};
use sea_plant::PlantOutputs;

/// The observer and its sensor buffers, allocated once.
pub(super) struct DisturbanceObserverLoop {
    observer: GeneralizedDisturbanceObserver,
    /// The sensed joint torques at the sample: after the command (n), and before it (the end
    /// of the period before; n).
    sensed: (DVector<f64>, DVector<f64>),
    /// The plant's joint torques (n) and contact wrenches (6 per contact) at the start of the
    /// last step of the period that ended at the current sample.
    previous_period_end: (DVector<f64>, DVector<f64>),
}

/// The forces at the end of a period (the start of its last plant step): the joint torques
/// (n) and contact wrenches (6 per contact) the plant had there.
pub(super) struct PeriodEnd<'a> {
    /// Joint torques (n) [Nm].
    pub joint_torque: &'a DVector<f64>,
    /// Contact wrenches (6 per contact) [N, Nm].
    pub contact_wrench: &'a DVector<f64>,
}

impl DisturbanceObserverLoop {
    /// The observer of `controller.external_wrench = "generalized"` for `controller`, or
    /// `None` when `observer` is.
    pub fn new(
        observer: Option<GeneralizedDisturbanceObserver>,
        controller: &MomentumController,
    ) -> Option<Self> {
        let (n, k) = (
            controller.model().n_joints(),
            6 * controller.contact_frames().len(),
        );
        observer.map(|observer| Self {
            observer,
            sensed: (DVector::zeros(n), DVector::zeros(n)),
            previous_period_end: (DVector::zeros(n), DVector::zeros(k)),
        })
    }

    /// One update at the sample (module doc) with the measured state `measured` (layout
    /// `layout`), the elastic estimates `estimates` (n_e, the joint loop's or the
    /// controller's), the plant's outputs `at_sample` at the start of the period and its
    /// forces `period_end` at the start of the period's last step; hands the estimate to
    /// `controller`.
    pub fn observe(
        &mut self,
        controller: &mut MomentumController,
        (layout, measured): (&StateLayout, &[f64]),
        estimates: &[ElasticParameters],
        at_sample: &PlantOutputs,
        period_end: PeriodEnd<'_>,
    ) {
        let elastic = (&controller.actuation().elastic_joints[..], estimates);
        let (after, before) = &mut self.sensed;
        sense_joint_torques(elastic, layout, measured, &at_sample.joint_torque, after);
        let (end_torques, end_wrenches) = &mut self.previous_period_end;
        sense_joint_torques(elastic, layout, measured, end_torques, before);
        let robot = (controller.model(), controller.contact_frames());
        let state = (layout.q(measured), layout.nu(measured));
        let before = AppliedForces {
            joint_torques: before,
            contact_wrenches: end_wrenches,
        };
        let after = AppliedForces {
            joint_torques: after,
            contact_wrenches: &at_sample.contact_wrench,
        };
        let estimate = self.observer.update(robot, state, before, after);
        controller
            .set_generalized_disturbance(estimate)
            .expect("the observer is sized for the controller's model");
        controller.set_com_offset(self.observer.com_offset());
        end_torques.copy_from(period_end.joint_torque);
        end_wrenches.copy_from(period_end.contact_wrench);
    }
}

/// The joint torques (n) as the robot senses them at state `x`: an elastic joint's (of
/// `elastic`: coordinate indices and the loop's estimates) from its deflection through the
/// estimates ([`sea_ctrl::sea::sensed_spring_torque`]), a rigid joint's the torque applied
/// (`applied`, n: its motor's torque).
fn sense_joint_torques(
    (elastic_joints, estimates): (&[usize], &[ElasticParameters]),
    layout: &StateLayout,
    x: &[f64],
    applied: &DVector<f64>,
    sensed: &mut DVector<f64>,
) {
    sensed.copy_from(applied);
    let (theta, thetadot) = (layout.theta(x), layout.thetadot(x));
    let (s, sdot) = (layout.s(x), layout.sdot(x));
    for (e, (&j, estimate)) in elastic_joints.iter().zip(estimates).enumerate() {
        let motor = (theta[e], thetadot[e]);
        sensed[j] = sea_ctrl::sea::sensed_spring_torque(estimate, motor, (s[j], sdot[j]));
    }
}
