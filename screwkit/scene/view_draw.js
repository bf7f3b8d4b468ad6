/* screwkit's 3D view of a PM, part 1 of 3: the traces of one state (plotly.js, bundled in the
 * page).  The three parts (view_draw.js, view_labels.js, view_page.js) are joined inside one
 * function by screwkit.scene._page; they share its scope.  The data is the JSON of
 * screwkit.scene.Scene.to_json(), in the script element #screwkit-data. */
var D = JSON.parse(document.getElementById("screwkit-data").textContent);
var plot = document.getElementById("sk-plot");
var size = D.size, C = D.colors, U = D.units;
var ARROW = 0.6;      // the longest arrow of a kind, times the drawing's size (screwkit draw's)
var CLEAR = 0.1;      // a constraint force slid this far (times size) off a marker it starts on
var GAP = 0.04;       // an actuation force drawn outside its leg stops this far before a

// -- small vector algebra ------------------------------------------------------------------
function add(a, b) { return [a[0] + b[0], a[1] + b[1], a[2] + b[2]]; }
function sub(a, b) { return [a[0] - b[0], a[1] - b[1], a[2] - b[2]]; }
function mul(a, s) { return [a[0] * s, a[1] * s, a[2] * s]; }
function dot(a, b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
function cross(a, b) {
  return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
}
function norm(a) { return Math.sqrt(dot(a, a)); }
function unit(a) { var n = norm(a); return n > 0 ? mul(a, 1 / n) : [0, 0, 1]; }
function normal(d) {            // a unit vector normal to d
  var t = Math.abs(d[0]) < 0.9 ? [1, 0, 0] : [0, 1, 0];
  return unit(cross(d, t));
}

// -- accumulators: polylines separated by nulls, triangle meshes ---------------------------
function Lines() { this.x = []; this.y = []; this.z = []; this.text = []; }
Lines.prototype.path = function (pts, text) {
  for (var i = 0; i < pts.length; i++) {
    this.x.push(pts[i][0]); this.y.push(pts[i][1]); this.z.push(pts[i][2]);
    this.text.push(text || "");
  }
  this.x.push(null); this.y.push(null); this.z.push(null); this.text.push("");
};
function Points() { this.x = []; this.y = []; this.z = []; this.text = []; }
Points.prototype.add = function (p, text) {
  this.x.push(p[0]); this.y.push(p[1]); this.z.push(p[2]); this.text.push(text);
};
function Mesh() { this.x = []; this.y = []; this.z = []; this.i = []; this.j = []; this.k = []; }
Mesh.prototype.vertex = function (p) {
  this.x.push(p[0]); this.y.push(p[1]); this.z.push(p[2]);
  return this.x.length - 1;
};
Mesh.prototype.tri = function (a, b, c) { this.i.push(a); this.j.push(b); this.k.push(c); };
Mesh.prototype.fan = function (poly) {
  var c = [0, 0, 0];
  poly.forEach(function (p) { c = add(c, mul(p, 1 / poly.length)); });
  var ic = this.vertex(c), first = this.x.length;
  for (var n = 0; n < poly.length; n++) { this.vertex(poly[n]); }
  for (n = 0; n < poly.length; n++) {
    this.tri(ic, first + n, first + (n + 1) % poly.length);
  }
};
// a box of half-length hl along d and half-width hw around the centre c; its edges to lines
Mesh.prototype.box = function (c, d, hl, hw, edges) {
  var e1 = normal(d), e2 = cross(d, e1), v = [], self = this;
  [-1, 1].forEach(function (s) {
    [[1, 1], [-1, 1], [-1, -1], [1, -1]].forEach(function (q) {
      v.push(add(add(c, mul(d, s * hl)), add(mul(e1, q[0] * hw), mul(e2, q[1] * hw))));
    });
  });
  var id = v.map(function (p) { return self.vertex(p); });
  var faces = [[0, 1, 2, 3], [4, 5, 6, 7], [0, 1, 5, 4], [1, 2, 6, 5], [2, 3, 7, 6], [3, 0, 4, 7]];
  faces.forEach(function (f) {
    self.tri(id[f[0]], id[f[1]], id[f[2]]);
    self.tri(id[f[0]], id[f[2]], id[f[3]]);
  });
  if (edges) {
    edges.path([v[0], v[1], v[2], v[3], v[0]]);
    edges.path([v[4], v[5], v[6], v[7], v[4]]);
    for (var n = 0; n < 4; n++) { edges.path([v[n], v[n + 4]]); }
  }
};

// -- the line of a force clipped to the view's box -----------------------------------------
function clip(p, d) {
  var s0 = -Infinity, s1 = Infinity, lo = D.box.lo, hi = D.box.hi;
  for (var k = 0; k < 3; k++) {
    if (Math.abs(d[k]) < 1e-12) { if (p[k] < lo[k] || p[k] > hi[k]) { return null; } continue; }
    var a = (lo[k] - p[k]) / d[k], b = (hi[k] - p[k]) / d[k];
    s0 = Math.max(s0, Math.min(a, b)); s1 = Math.min(s1, Math.max(a, b));
  }
  return s1 > s0 ? [add(p, mul(d, s0)), add(p, mul(d, s1))] : null;
}

function line(acc, name, color, width, extra) {
  var t = {type: "scatter3d", mode: "lines", name: name, x: acc.x, y: acc.y, z: acc.z,
           line: {color: color, width: width}, hoverinfo: "text", text: acc.text};
  return Object.assign(t, extra || {});
}
function mesh(m, name, color, opacity, extra) {
  var t = {type: "mesh3d", name: name, x: m.x, y: m.y, z: m.z, i: m.i, j: m.j, k: m.k,
           color: color, opacity: opacity, flatshading: true, hoverinfo: "skip"};
  t = Object.assign(t, extra || {});
  if (!m.i.length) { t.showlegend = false; }   // a kind the PM does not have: not in the legend
  return t;
}
function markers(p, name, color, msize, extra) {
  var t = {type: "scatter3d", mode: "markers", name: name, x: p.x, y: p.y, z: p.z,
           text: p.text, hoverinfo: "text",
           marker: {color: color, size: msize, line: {color: "white", width: 1}}};
  return Object.assign(t, extra || {});
}
function legendOnly(name, color, dash, width, group) {
  return {type: "scatter3d", mode: "lines", name: name, x: [null], y: [null], z: [null],
          line: {color: color, dash: dash || "solid", width: width || 4},
          legendgroup: group || name, hoverinfo: "skip", showlegend: true};
}
function cone(tip, vec, color, opacity, group) {
  if (!(opacity > 0 && norm(vec) > 0)) {     // a placeholder: keeps the traces in order
    return {type: "cone", x: [0], y: [0], z: [0], u: [0], v: [0], w: [1], visible: false,
            showscale: false, showlegend: false, legendgroup: group};
  }
  return {type: "cone", x: [tip[0]], y: [tip[1]], z: [tip[2]], u: [vec[0]], v: [vec[1]],
          w: [vec[2]], anchor: "tip", sizemode: "raw", showscale: false, opacity: opacity,
          colorscale: [[0, color], [1, color]], hoverinfo: "skip", showlegend: false,
          legendgroup: group, lighting: {ambient: 0.9, diffuse: 0.4}};
}

function fmt(v) {
  if (v === null || !isFinite(v)) { return "n/a"; }
  var a = Math.abs(v);
  if (a === 0) { return "0"; }
  if (a < 1e-3 || a >= 1e6) { return v.toExponential(3); }
  return String(parseFloat(v.toPrecision(4)));
}

// -- the joints, drawn by kind (the traces of one state: always the same number and order) --
function jointTraces(s) {
  var axes = new Lines(), helices = new Lines(), crosses = new Lines(), pa = new Lines();
  var sleeves = new Mesh(), edges = new Lines(), balls = new Points(), ucentres = new Points();
  var hover = new Points(), ends = new Points();
  var ax = 0.12 * size, hl = 0.08 * size, hw = 0.028 * size;
  s.legs.forEach(function (leg, i) {
    var tag = "leg " + (i + 1) + ": ";
    ends.add(leg.A, "A" + (i + 1)); ends.add(leg.a, "a" + (i + 1));
    leg.joints.forEach(function (j) {
      var name = tag + j.name + (j.act ? " (actuated)" : "");
      var p = j.p, d = j.d;
      if (j.k === "S") { balls.add(p, name + ": S centre"); return; }
      if (j.k === "U") {
        crosses.path([sub(p, mul(d, ax)), add(p, mul(d, ax))], name);
        crosses.path([sub(p, mul(j.d2, ax)), add(p, mul(j.d2, ax))], name);
        ucentres.add(p, name + ": U centre"); return;
      }
      if (j.k === "P" || j.k === "C") {
        sleeves.box(p, d, hl, hw, edges);
        hover.add(p, name + (j.k === "C" ? ": C (sleeve on its axis)" : ": P sleeve"));
        if (j.k === "C") { axes.path([sub(p, mul(d, 1.5 * ax)), add(p, mul(d, 1.5 * ax))], name); }
        return;
      }
      if (j.k === "Pa") {
        var w = 0.08 * size, c = [sub(p, mul(d, w)), add(p, mul(d, w)),
                                  add(add(p, mul(d, w)), j.bar), add(sub(p, mul(d, w)), j.bar)];
        pa.path([c[0], c[1], c[2], c[3], c[0]], name + ": parallelogram");
        c.forEach(function (q) {
          axes.path([sub(q, mul(j.hinge, 0.3 * ax)), add(q, mul(j.hinge, 0.3 * ax))], name);
        });
        hover.add(add(p, mul(j.bar, 0.5)), name + ": Pa parallelogram");
        return;
      }
      axes.path([sub(p, mul(d, ax)), add(p, mul(d, ax))], name);
      if (j.k === "H") {       // a helix of three turns around the axis
        var e1 = normal(d), e2 = cross(d, e1), pts = [], r = 0.035 * size;
        for (var n = 0; n <= 72; n++) {
          var th = n / 72 * 6 * Math.PI;
          pts.push(add(add(p, mul(d, -ax + 2 * ax * n / 72)),
                       add(mul(e1, r * Math.cos(th)), mul(e2, r * Math.sin(th)))));
        }
        helices.path(pts, name + ": H, pitch " + fmt(j.pitch) + " " + U.length + "/rad");
        hover.add(p, name + ": H, pitch " + fmt(j.pitch) + " " + U.length + "/rad");
      } else {
        hover.add(p, name + ": R axis");
      }
    });
  });
  return [
    line(axes, "R axis", C.R, 7, {legendgroup: "R"}),
    line(helices, "H axis (helix: its pitch)", C.R, 2, {legendgroup: "H"}),
    mesh(sleeves, "P sleeve", C.P_fill, 1.0, {showlegend: true, legendgroup: "P"}),
    line(edges, "P sleeve edges", C.P, 2, {showlegend: false, legendgroup: "P"}),
    markers(balls, "S ball", C.S, 13, {legendgroup: "S"}),
    line(crosses, "U cross", C.U, 6, {legendgroup: "U"}),
    markers(ucentres, "U centre", C.U, 5, {showlegend: false, legendgroup: "U"}),
    line(pa, "Pa parallelogram", C.P, 4, {legendgroup: "Pa"}),
    markers(hover, "joint", C.R, 2, {showlegend: false, opacity: 0.6}),
    markers(ends, "end points A_i (base), a_i (platform)", C.end, 3,
            {marker: {color: C.end, size: 4, symbol: "square"}})
  ];
}

// an S or U centre or an end point of a leg: a marker is drawn there
function onMarker(s, p) {
  return s.legs.some(function (leg) {
    var pts = [leg.A, leg.a];
    leg.joints.forEach(function (j) { if (j.k === "S" || j.k === "U") { pts.push(j.p); } });
    return pts.some(function (q) { return norm(sub(q, p)) <= 1e-6 * size; });
  });
}

// How clear of the legs' chains the segment p-q is on the screen (proj): the sum, over points
// along it, of their distances (pixels, up to 20) to the nearest chain
function clearance(s, p, q, proj) {
  var segs = [];
  s.legs.forEach(function (leg) {
    for (var n = 1; n < leg.chain.length; n++) {
      segs.push([proj(leg.chain[n - 1]), proj(leg.chain[n])]);
    }
  });
  var total = 0;
  for (var t = 0.3; t <= 1.0001; t += 0.1) {
    var x = proj(add(p, mul(sub(q, p), t))), best = 20;
    segs.forEach(function (g) { best = Math.min(best, toSegment(x, g[0], g[1])); });
    total += best;
  }
  return total;
}

// Where each row's arrow goes at state s: null (nothing drawn) or its tail, head, unit
// direction u and, for a couple, the point of its leg it is tied to.  The lengths are the
// state's "frac" (screwkit.scene.arrow_fractions: per kind, with a floor).  A force sits on
// its line where the line passes nearest to a; an actuation force that would run back down
// its own leg (hidden by it) is drawn on the far side of a, pointing at a; a constraint force
// that would start on a ball or an end point is slid along its line clear of it, to the side
// (starting there, or ending there) where it stands clearer of the chains on the screen
// (proj, when given).
function arrows(s, proj) {
  var seen = {};
  return D.rows.map(function (r, k) {
    var leg = s.legs[r.leg], dir = s.directions[k], frac = s.frac[k];
    if (!leg || !dir || dir[0] === null || frac === null) { return null; }
    var vec = mul(dir, frac * ARROW * size), u = unit(vec), tail, head = null, tie = null;
    if (r.kind === "couple") {     // a free vector: beside its leg, tied to it by a dotted line
      var n = seen[r.leg] || 0;
      seen[r.leg] = n + 1;
      tie = add(leg.A, mul(sub(leg.a, leg.A), 0.5 + 0.12 * n));
      var side = cross(unit(sub(leg.a, leg.A)), dir);
      side = norm(side) < 1e-6 ? normal(sub(leg.a, leg.A)) : unit(side);
      tail = add(tie, mul(side, 0.22 * size));
    } else {
      var q = s.points[k], last = leg.chain[leg.chain.length - 2] || leg.A;
      tail = add(q, mul(dir, dot(sub(leg.a, q), dir)));
      if (r.actuation && dot(u, unit(sub(leg.a, last))) < -0.9) {
        head = sub(tail, mul(u, GAP * size));
        tail = sub(head, vec);
      } else if (!r.actuation && onMarker(s, tail)) {   // slide it clear of the ball it hides in
        var from = add(tail, mul(u, CLEAR * size)), to = sub(tail, mul(u, CLEAR * size));
        if (proj && clearance(s, to, sub(to, vec), proj) > clearance(s, from, add(from, vec), proj)) {
          head = to;
          tail = sub(to, vec);
        } else {
          tail = from;
        }
      }
    }
    return {tail: tail, head: head || add(tail, vec), u: u, tie: tie, dir: dir};
  });
}

// the view's box: the scene's, grown to every arrow of every state (fixed: the view does not
// rescale as the pose moves)
D.states.forEach(function (s) {
  arrows(s).forEach(function (a) {
    if (!a) { return; }
    [a.tail, a.head].forEach(function (p) {
      for (var k = 0; k < 3; k++) {
        D.box.lo[k] = Math.min(D.box.lo[k], p[k] - 0.05 * size);
        D.box.hi[k] = Math.max(D.box.hi[k], p[k] + 0.05 * size);
      }
    });
  });
});

var HEAD = 0.09;      // an arrow head's length, times size
function wrenchTraces(s, geo) {
  var out = [];
  var actions = D.legs.map(function () { return new Lines(); });
  var ties = D.legs.map(function () { return new Lines(); });
  D.rows.forEach(function (r, k) {
    var group = "leg" + r.leg, color = D.legs[r.leg].color, a = geo[k];
    var shaft = new Lines(), act = r.actuation, couple = r.kind === "couple";
    if (!a) {
      out.push(line(shaft, r.label, color, 5, {showlegend: false, legendgroup: group}));
      out.push(cone([0, 0, 0], [0, 0, 0], color, 0, group));
      out.push(cone([0, 0, 0], [0, 0, 0], color, 0, group));
      return;
    }
    if (couple) {
      ties[r.leg].path([a.tie, a.tail]);
    } else {
      var seg = clip(a.tail, a.dir);
      if (seg) { actions[r.leg].path(seg); }
    }
    // a short arrow (at the floor) keeps a shaft: its head at most 40 % of it
    var text = s.text[k], pale = act ? 1.0 : 0.7;
    var headLen = Math.min(HEAD * size, 0.4 * norm(sub(a.head, a.tail)));
    shaft.path([a.tail, sub(a.head, mul(a.u, 0.8 * headLen))], text);
    out.push(line(shaft, r.label, color, act ? 9 : 6,
                  {showlegend: false, legendgroup: group, hoverinfo: "text"}));
    out.push(cone(a.head, mul(a.u, headLen), color, pale, group));
    out.push(cone(sub(a.head, mul(a.u, 0.9 * headLen)), mul(a.u, couple ? headLen : 0), color,
                  couple ? pale : 0, group));
  });
  D.legs.forEach(function (lg, i) {
    out.push(line(actions[i], "line of action", lg.color, 3,
                  {showlegend: false, legendgroup: "leg" + i, line: {color: lg.color, width: 3,
                   dash: "dot"}, opacity: 0.7, hoverinfo: "skip"}));
    out.push(line(ties[i], "couple tie", lg.color, 2,
                  {showlegend: false, legendgroup: "leg" + i, line: {color: lg.color, width: 2,
                   dash: "dot"}, hoverinfo: "skip"}));
  });
  return out;
}

function traces(s, geo) {
  var base = new Mesh(), plat = new Mesh(), baseEdge = new Lines(), platEdge = new Lines();
  if (s.base.length >= 3) { base.fan(s.base); }
  if (s.base.length) { baseEdge.path(s.base.concat([s.base[0]]), "base"); }
  if (s.platform.length >= 3) { plat.fan(s.platform); }
  if (s.platform.length) { platEdge.path(s.platform.concat([s.platform[0]]), "platform"); }
  var out = [
    mesh(base, "base", C.base, 0.45, {showlegend: true, legendgroup: "base"}),
    line(baseEdge, "base edge", "#636363", 3, {showlegend: false, legendgroup: "base"}),
    mesh(plat, "platform", C.platform, 0.6, {showlegend: true, legendgroup: "platform"}),
    line(platEdge, "platform edge", "#525252", 3, {showlegend: false, legendgroup: "platform"})
  ];
  D.legs.forEach(function (lg, i) {
    var chain = new Lines(), leg = s.legs[i];
    if (leg) { chain.path(leg.chain, lg.label); } else { chain.path([[null, null, null]]); }
    out.push(line(chain, lg.label, lg.color, 7, {legendgroup: "leg" + i, opacity: 0.8,
                                                line: {color: lg.color, width: 7,
                                                       dash: lg.passive ? "dash" : "solid"}}));
  });
  out = out.concat(jointTraces(s));
  var o = new Points();
  if (s.o) { o.add(s.o, "o (platform centre: the workload acts here)"); }
  out.push(markers(o, "o (where the workload acts)", "#252525", 5));
  out = out.concat(wrenchTraces(s, geo));
  // the legend names the kinds of arrow this PM has, and no other
  function has(test) { return D.rows.some(test); }
  if (has(function (r) { return r.actuation && r.kind !== "couple"; })) {
    out.push(legendOnly("actuation force: thick shaft, full head", "#333333", "solid", 8,
                        "kinds"));
  }
  if (has(function (r) { return r.kind === "force"; })) {
    out.push(legendOnly("constraint force: thin shaft, pale head", "#888888", "solid", 4,
                        "kinds"));
  }
  if (has(function (r) { return r.kind === "couple"; })) {
    out.push(legendOnly("couple: two heads, beside its leg", "#888888", "solid", 4, "kinds"));
  }
  if (has(function (r) { return r.kind !== "couple"; })) {
    out.push(legendOnly("line of action of a force", "#555555", "dot", 2, "kinds"));
  }
  return out;
}
