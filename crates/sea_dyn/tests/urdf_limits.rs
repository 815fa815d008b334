//! The size a URDF may have: a model refuses a robot beyond
//! [`sea_dyn::urdf::MAX_MOVING_JOINTS`] moving joints, naming it, before it builds the parts
//! that grow with the square of the count.

use sea_dyn::{LoadOptions, Model};

#[test]
fn a_chain_beyond_the_most_moving_joints_is_refused_naming_the_robot() {
    let most = sea_dyn::urdf::MAX_MOVING_JOINTS;
    let chain = |joints: usize| {
        let link = |i: usize| {
            format!(
                "<link name=\"l{i}\"><inertial><mass value=\"1\"/><inertia ixx=\"0.01\" \
                 iyy=\"0.01\" izz=\"0.01\" ixy=\"0\" ixz=\"0\" iyz=\"0\"/></inertial></link>"
            )
        };
        let joint = |i: usize| {
            format!(
                "<joint name=\"j{i}\" type=\"continuous\"><parent link=\"l{}\"/>\
                 <child link=\"l{i}\"/><axis xyz=\"0 1 0\"/></joint>",
                i - 1
            )
        };
        let links: String = (0..=joints).map(link).collect();
        let joints: String = (1..=joints).map(joint).collect();
        format!("<robot name=\"chain\">{links}{joints}</robot>")
    };
    let model = Model::from_urdf_str(&chain(most), &LoadOptions::default()).unwrap();
    assert_eq!(model.n_joints(), most);
    let error = Model::from_urdf_str(&chain(most + 1), &LoadOptions::default()).unwrap_err();
    let message = error.to_string();
    assert!(
        message.contains("robot 'chain'")
            && message.contains(&format!("{} moving joints", most + 1)),
        "{message}"
    );
}
