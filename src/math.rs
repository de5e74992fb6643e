//! Small geometric helpers shared by the kinematics and the force elements.
