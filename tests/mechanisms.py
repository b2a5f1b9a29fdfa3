"""Mechanism texts shared by several test modules."""

_RSSR_POINTS = {"A0": (0, 0, 0), "D0": (1, 0, 0.3), "A": (0.2, 0.1, 0), "B": (0.9, 0.7, 0.5)}


def rssr(unit: str = "m", scale: float = 1.0, driver: bool = True) -> str:
    """A spatial RSSR crank-rocker (revolutes at A0 and D0, spherical joints at A and B):
    Somov–Malyshev W = 6·3 − 5·2 − 3·2 = 2 (one idle spin of the coupler)."""
    pts = "\n".join(f"{n} = [{', '.join(f'{c * scale:g}' for c in xyz)}]" for n, xyz in _RSSR_POINTS.items())
    text = f"""
format = "assur/1"
dimension = 3
[units]
length = "{unit}"
angle = "deg"
[points]
{pts}
[links]
frame = ["A0", "D0"]
crank = ["A0", "A"]
coupler = ["A", "B"]
rocker = ["D0", "B"]
[joints]
A = "spherical"
B = "spherical"
"""
    if driver:
        text += '[[drivers]]\nname = "crank"\nlink = "crank"\npivot = "A0"\narm = "A"\n'
    return text
