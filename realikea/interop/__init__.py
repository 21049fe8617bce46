"""Other simulators on the exported library: the MuJoCo checks of the resistance and the finger gap
run again on the exported URDF in PyBullet and compared."""
