//! `external_wrench = "generalized"` in the controller stack: the generalized disturbance
//! observer ([`crate::generalized_disturbance`]) fed with what the robot's sensors read over a
//! whole-body period, and its estimate handed to the controller.
//!
//! At tick `k`, after the period that starts there: the measured state (the encoders), the
//! joint torques as the robot senses them (an elastic joint's deflection through the stack's
//! stiffness and damping estimates, a rigid joint's motor torque) and the feet's wrenches, at
//! the start of that period (`g_k^+`) and at the end of the period before (`g_k^-`: the
//! wrenches and rigid torques read at its end; the elastic torques, a function of the state,
//! from the measurement at `k`).

use super::sensors::{ForceReadings, PeriodSensors};
use crate::generalized_disturbance::{AppliedForces, GeneralizedDisturbanceObserver};
use crate::MomentumController;
use nalgebra::DVector;
use sea_dyn::{ElasticParameters, StateLayout};

/// The observer and its sensor buffers, allocated once.
#[derive(Clone, Debug)]
pub struct DisturbanceObserverLoop {
    observer: GeneralizedDisturbanceObserver,
    /// The sensed joint torques at the tick: after the command (n), and before it (the end of
    /// the period before; n).
    sensed: (DVector<f64>, DVector<f64>),
    /// The joint torques (n) and contact wrenches (6 per contact) read at the end of the
    /// period that ended at the current tick.
    previous_period_end: (DVector<f64>, DVector<f64>),
}

impl DisturbanceObserverLoop {
    /// `observer` run for `controller`.
    pub fn new(observer: GeneralizedDisturbanceObserver, controller: &MomentumController) -> Self {
        let (n, k) = (
            controller.model().n_joints(),
            6 * controller.contact_frames().len(),
        );
        Self {
            observer,
            sensed: (DVector::zeros(n), DVector::zeros(n)),
            previous_period_end: (DVector::zeros(n), DVector::zeros(k)),
        }
    }

    /// One update after the period (module doc) with the measured state `measured` (layout
    /// `layout`) at its start, the elastic estimates `estimates` (n_e, the joint loops' or the
    /// controller's) and the period's `sensors`; hands the estimate to `controller`.
    pub fn observe(
        &mut self,
        controller: &mut MomentumController,
        (layout, measured): (&StateLayout, &[f64]),
        estimates: &[ElasticParameters],
        sensors: PeriodSensors<'_>,
    ) {
        let elastic = (&controller.actuation().elastic_joints[..], estimates);
        let (after, before) = &mut self.sensed;
        let start = sensors.start;
        sense_joint_torques(elastic, layout, measured, start.joint_torque, after);
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
            contact_wrenches: start.contact_wrench,
        };
        let estimate = self.observer.update(robot, state, before, after);
        controller
            .set_generalized_disturbance(estimate)
            .expect("the observer is sized for the controller's model");
        controller.set_com_offset(self.observer.com_offset());
        let ForceReadings {
            contact_wrench,
            joint_torque,
        } = sensors.end;
        end_torques.copy_from(joint_torque);
        end_wrenches.copy_from(contact_wrench);
    }
}

/// The joint torques (n) as the robot senses them at state `x`: an elastic joint's (of
/// `elastic`: coordinate indices and the estimates) from its deflection through the estimates
/// ([`crate::sea::sensed_spring_torque`]), a rigid joint's the torque applied (`applied`, n:
/// its motor's torque).
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
        sensed[j] = crate::sea::sensed_spring_torque(estimate, motor, (s[j], sdot[j]));
    }
}
