"""A Tricept-type 3UPS+UP/passive model file (docs/pm_models.md): three actuated UPS legs and
a passive UP column, for the tests of passive legs in the view and the MJCF export."""

TRICEPT = """\
units: {length: mm, force: N}
legs:
  - name: UP/column
    string: U_P
    joints:
      - {at: A, axes: [base.X, {perpendicular: [U1a, leg]}]}
      - {axis: leg}
    structure:
      - {perpendicular: [U1b, leg]}
pms:
  tricept:
    string: 3UPS+UP/passive
    dimensions: {R: 300, r: 110, H: 650}
    base: {points: [[R, 0, 0], [-R/2, R*sqrt(3)/2, 0], [-R/2, -R*sqrt(3)/2, 0], [0, 0, 0]]}
    platform: {points: [[r, 0, 0], [-r/2, r*sqrt(3)/2, 0], [-r/2, -r*sqrt(3)/2, 0], [0, 0, 0]]}
    legs: [UPS, UPS, UPS, {leg: UP/column, passive: true}]
    euler: XYZ
    independent: [alpha, beta, Zo]
    pose: {alpha: 5, beta: -3, Zo: H}
    dof: 3
    motion: 1T2R
"""
