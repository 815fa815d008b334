//! `sea_dyn`: floating-base rigid-body dynamics from URDF for robots with series elastic
//! actuators.
//!
//! Model/Data split as in Pinocchio: [`Model`] is immutable (built by
//! [`Model::from_urdf_file`]); [`Data`] owns every buffer; the algorithms are free functions,
//! one file each with its equation in the header, that write into `Data` and allocate nothing.
//!
//! Conventions: `q = [p_B (world); quaternion (w, x, y, z); s]` (nq = 7 + n),
//! `nu = [pdot_B (world); omega_B (world); sdot]` (nv = 6 + n), spatial vectors linear first,
//! `M(q) nudot + h(q, nu) = B tau + sum_k J_k^T f_k`, gravity -9.81 m/s^2 along world z.
//!
//! ```
//! use sea_dyn::{Data, LoadOptions, Model};
//! let urdf = r#"<robot name="r">
//!   <link name="base"><inertial><mass value="1"/>
//!     <inertia ixx="0.1" ixy="0" ixz="0" iyy="0.1" iyz="0" izz="0.1"/></inertial></link>
//!   <link name="arm"><inertial><origin xyz="0 0 0.5"/><mass value="1"/>
//!     <inertia ixx="0.1" ixy="0" ixz="0" iyy="0.1" iyz="0" izz="0.1"/></inertial></link>
//!   <joint name="shoulder" type="revolute"><parent link="base"/><child link="arm"/>
//!     <axis xyz="0 1 0"/><limit lower="-1" upper="1" effort="10" velocity="1"/></joint>
//! </robot>"#;
//! let model = Model::from_urdf_str(urdf, &LoadOptions::default()).unwrap();
//! let mut data = Data::new(&model);
//! let q = model.neutral();
//! let m = sea_dyn::crba(&model, &mut data, &q);
//! assert_eq!(m.nrows(), 7);
//! ```

#![forbid(unsafe_code)]

pub mod algorithms;
#[cfg(feature = "serde")]
pub mod bounded;
pub mod error;
pub mod files;
pub mod gains;
pub mod linalg;
pub mod model;
pub mod sample;
pub mod spatial;

// The algorithm, model and linear-algebra files keep short paths (`sea_dyn::rnea`, ...).
pub use algorithms::{centroidal, crba, jacobian, kinematics, rnea, split};
pub use linalg::{dense, tree_factor};
pub use model::{actuator, configuration, contact_surface, data, resources, state, urdf};

pub use actuator::{Actuation, Actuator, ElasticParameters};
pub use centroidal::{
    centroidal_momentum, centroidal_momentum_bias, centroidal_momentum_from_dynamics,
    centroidal_momentum_matrix, com, com_jacobian,
};
pub use configuration::integrate;
pub use contact_surface::ContactSurface;
pub use crba::{crba, crba_after_rnea, crba_from_kinematics};
pub use data::Data;
pub use error::{Error, Result, Warning, WarningKind};
pub use gains::critical_damping;
pub use jacobian::{frame_jacobian, frame_jacobian_dot_v};
pub use kinematics::{
    forward_kinematics, forward_kinematics_path, forward_velocities, forward_velocities_path,
    frame_placement,
};
pub use model::{Frame, FrameId, Joint, JointKind, Model};
pub use resources::PackageDirs;
pub use rnea::{bias_forces, gravity_forces, rnea};
pub use split::CentroidalSplit;
pub use state::{StateLayout, TangentBlocks, TangentLayout};
pub use urdf::LoadOptions;
