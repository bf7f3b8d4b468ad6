/* screwkit's 3D view, part 2 of 3: the value labels, placed beside their own arrows.
 *
 * Each label is a plotly 3D annotation tied to its arrow's head by a leader in the leg's
 * colour; its offset on the screen is chosen among 16 directions x 5 distances around the
 * head, for the least cost: covering another label (worst), an arrow's shaft or head, a
 * joint, a leg's chain, the polygons' edges; standing nearer another arrow than its own;
 * sitting ahead of its arrow rather than beside it; distance.  The screen positions come
 * from plotly's own camera once the scene is drawn (and again after the user turns the
 * view), else from an orthographic estimate of the default camera. */

// plotly's projection of the drawn scene (its camera and data scale; pixels, y downwards),
// or null before the scene exists
function sceneProjector() {
  var fl = plot._fullLayout, sc = fl && fl.scene && fl.scene._scene;
  if (!sc || !sc.glplot || !sc.glplot.cameraParams || !sc.dataScale) { return null; }
  var cp = sc.glplot.cameraParams, ds = sc.dataScale, w = fl._size.w, h = fl._size.h;
  var dom = fl.scene.domain;
  function mv(m, v) {
    var r = [0, 0, 0, 0];
    for (var i = 0; i < 4; ++i) { for (var n = 0; n < 4; ++n) { r[n] += m[4 * i + n] * v[i]; } }
    return r;
  }
  return function (p) {
    var r = mv(cp.projection, mv(cp.view, mv(cp.model, [p[0] * ds[0], p[1] * ds[1],
                                                        p[2] * ds[2], 1])));
    return [0.5 * (1 + r[0] / r[3]) * w * (dom.x[1] - dom.x[0]),
            0.5 * (1 - r[1] / r[3]) * h * (dom.y[1] - dom.y[0])];
  };
}

// an orthographic estimate of the default camera, before plotly has drawn the scene
function estimateProjector() {
  var e = layout.scene.camera.eye, ar = layout.scene.aspectratio;
  var view = unit([-e.x, -e.y, -e.z]), right = unit(cross(view, [0, 0, 1]));
  var up = cross(right, view);
  var scale = [ar.x / (hi[0] - lo[0]), ar.y / (hi[1] - lo[1]), ar.z / (hi[2] - lo[2])];
  var mid = mul(add(lo, hi), 0.5);
  var px = 0.62 * Math.min(plot.clientWidth || 900, layout.height);
  return function (p) {
    var n = [(p[0] - mid[0]) * scale[0], (p[1] - mid[1]) * scale[1], (p[2] - mid[2]) * scale[2]];
    return [px * dot(n, right), -px * dot(n, up)];
  };
}

// the length (pixels) of the segment a-b inside the box [x0, y0, x1, y1] (Liang-Barsky)
function inside(a, b, box) {
  var t0 = 0, t1 = 1, dx = b[0] - a[0], dy = b[1] - a[1];
  var p = [-dx, dx, -dy, dy], q = [a[0] - box[0], box[2] - a[0], a[1] - box[1], box[3] - a[1]];
  for (var i = 0; i < 4; i++) {
    if (p[i] === 0) { if (q[i] < 0) { return 0; } continue; }
    var t = q[i] / p[i];
    if (p[i] < 0) { t0 = Math.max(t0, t); } else { t1 = Math.min(t1, t); }
    if (t0 > t1) { return 0; }
  }
  return (t1 - t0) * Math.sqrt(dx * dx + dy * dy);
}
// the distance (pixels) from p to the segment a-b
function toSegment(p, a, b) {
  var dx = b[0] - a[0], dy = b[1] - a[1], l2 = dx * dx + dy * dy;
  var t = l2 > 0 ? Math.max(0, Math.min(1, ((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / l2)) : 0;
  var x = a[0] + t * dx - p[0], y = a[1] + t * dy - p[1];
  return Math.sqrt(x * x + y * y);
}

// what a label must keep off, on the screen: segments {a, b, w, row} and discs {c, r, w, row}
function obstacles(s, geo, proj) {
  var segs = [], discs = [];
  geo.forEach(function (a, k) {
    if (!a) { return; }
    segs.push({a: proj(a.tail), b: proj(a.head), w: 3, row: k});
    discs.push({c: proj(a.head), r: 7, w: 12, row: k});
    if (a.tie) { segs.push({a: proj(a.tie), b: proj(a.tail), w: 0.5, row: k}); }
  });
  s.legs.forEach(function (leg) {
    for (var n = 1; n < leg.chain.length; n++) {
      segs.push({a: proj(leg.chain[n - 1]), b: proj(leg.chain[n]), w: 1, row: -1});
    }
    [leg.A, leg.a].forEach(function (p) { discs.push({c: proj(p), r: 5, w: 4, row: -1}); });
    leg.joints.forEach(function (j) {
      discs.push({c: proj(j.p), r: j.k === "S" ? 8 : 6, w: 4, row: -1});
    });
  });
  [s.base, s.platform].forEach(function (P) {
    for (var n = 0; n < P.length; n++) {
      segs.push({a: proj(P[n]), b: proj(P[(n + 1) % P.length]), w: 0.3, row: -1});
    }
  });
  if (s.o) { discs.push({c: proj(s.o), r: 4, w: 4, row: -1}); }
  return {segs: segs, discs: discs};
}

var RINGS = [24, 38, 55, 75, 100];
function placeLabels(s, geo, proj) {
  var obs = obstacles(s, geo, proj), items = [];
  geo.forEach(function (a, k) {
    if (a) { items.push({k: k, head: proj(a.head), tail: proj(a.tail), p: a.head}); }
  });
  var boxes = items.map(function () { return null; });

  function cost(n, box, dist, th) {
    var it = items[n], c = dist / 25;
    var w = box[2] - box[0], h = box[3] - box[1];
    boxes.forEach(function (b, m) {            // another label: the worst
      if (!b || m === n) { return; }
      var ox = Math.min(box[2], b[2]) - Math.max(box[0], b[0]) + 3;
      var oy = Math.min(box[3], b[3]) - Math.max(box[1], b[1]) + 3;
      if (ox > 0 && oy > 0) { c += 40 + 100 * ox * oy / (w * h); }
    });
    obs.segs.forEach(function (g) {
      var len = inside(g.a, g.b, [box[0] - 2, box[1] - 2, box[2] + 2, box[3] + 2]);
      if (len > 0) { c += g.w * (2 + len / 4); }
    });
    obs.discs.forEach(function (d) {
      var x = Math.max(box[0], Math.min(d.c[0], box[2])) - d.c[0];
      var y = Math.max(box[1], Math.min(d.c[1], box[3])) - d.c[1];
      if (x * x + y * y < (d.r + 2) * (d.r + 2)) { c += d.w; }
    });
    // nearer its own arrow than any other (who owns a label is read from the nearest arrow)
    var mid = [(box[0] + box[2]) / 2, (box[1] + box[3]) / 2];
    var own = toSegment(mid, it.tail, it.head);
    items.forEach(function (o, m) {
      if (m !== n && toSegment(mid, o.tail, o.head) < own) { c += 15; }
    });
    var d = [it.head[0] - it.tail[0], it.head[1] - it.tail[1]];
    var l = Math.sqrt(d[0] * d[0] + d[1] * d[1]) || 1;    // beside its arrow, not ahead
    c += 2 * Math.abs(Math.cos(th) * d[0] / l + Math.sin(th) * d[1] / l);
    return c;
  }
  function place(n) {
    var it = items[n], text = s.text[it.k], w = 7.2 * text.length + 8, h = 18, best = null;
    RINGS.forEach(function (dist) {
      for (var q = 0; q < 16; q++) {
        var th = q * Math.PI / 8, cx = it.head[0] + dist * Math.cos(th);
        var cy = it.head[1] + dist * Math.sin(th);
        var box = [cx - w / 2, cy - h / 2, cx + w / 2, cy + h / 2], c = cost(n, box, dist, th);
        if (!best || c < best.c) { best = {c: c, box: box, ax: cx - it.head[0], ay: cy - it.head[1]}; }
      }
    });
    boxes[n] = best.box;
    it.ax = best.ax; it.ay = best.ay;
  }
  for (var round = 0; round < 2; round++) {     // greedy, then each again with the others set
    for (var n = 0; n < items.length; n++) { place(n); }
  }
  return items.map(function (it) {
    var color = D.legs[D.rows[it.k].leg].color;
    return {x: it.p[0], y: it.p[1], z: it.p[2], text: s.text[it.k], showarrow: true,
            arrowhead: 0, arrowwidth: 1, arrowcolor: color, ax: it.ax, ay: it.ay,
            font: {color: color, size: 12}, bgcolor: "rgba(255,255,255,0.85)",
            bordercolor: color, borderwidth: 1, borderpad: 2};
  });
}
