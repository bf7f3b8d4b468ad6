"""A Delta-type 3-RRPaR model file (parallelogram legs, mm and N): overconstrained, its six
constraint couples are not determined by statics; for the view, drawing and MJCF tests."""

DELTA = """\
legs:
  - name: RRPaR/delta
    string: _RRPaR
    joints:
      - {axis: base.tangent, at: A}
      - {axis: base.tangent, at: {offset: A, along: base.OA, fraction: 0.5}}
      - {axis: {perpendicular: [R1, {toward: [R2, a]}]}, at: R2, to: a}
      - {axis: R1, at: a}
pms:
  3RRPaR:
    string: 3RRPaR
    units: {length: mm, force: N}
    dimensions: {R: 100, r: 40}
    base: {shape: circle, radius: R, count: 3}
    platform: {shape: circle, radius: r, count: 3}
    legs: [RRPaR/delta, RRPaR/delta, RRPaR/delta]
    independent: [Xo, Yo, Zo]
    pose: {Xo: 0, Yo: 0, Zo: -150}
    euler: xyz
    dof: 3
    motion: 3T
"""
