"""The incline model of the ``penedge simulate`` tests: a 100 m³ block (2500 kg/m³) on a
plane dipping 30° towards the East, the rock below it fixed; dry and without cohesion, its
limit equilibrium is F = tan φ / tan 30°."""


def incline(friction: float = 35) -> str:
    """The model's settings (no stages), with joints of friction angle `friction`."""
    return f"""
[domain]
type = "box"
min = [0, 0, 0]
max = [10, 2, 8]
[[joints]]
type = "plane"
name = "slide"
point = [5, 1, 3]
dip = 30
dip_direction = 90
[rock]
density = 2500
[joint_properties.default]
kn = 1e9
ks = 1e8
friction = {friction}
[[boundary]]
region = {{type = "below", point = [5, 1, 3], dip = 30, dip_direction = 90}}
condition = "fixed"
"""
