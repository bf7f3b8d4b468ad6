/* screwkit's 3D view of a PM: draws one state of the page's data with plotly.js (bundled in
 * the page) and moves between states with sliders (a grid of poses) or a time slider with
 * play/pause (a path).  The data is the JSON of screwkit.scene.Scene.to_json(), in the
 * script element #screwkit-data; window.screwkitView exposes it and the state shown. */
(function () {
  "use strict";
  var D = JSON.parse(document.getElementById("screwkit-data").textContent);
  var plot = document.getElementById("sk-plot");
  var size = D.size, C = D.colors, U = D.units;
  var current = D.start;

  // -- small vector algebra ----------------------------------------------------------------
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

  // -- accumulators: polylines separated by nulls, triangle meshes -------------------------
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

  // -- the line of a force clipped to the view's box ---------------------------------------
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
    return Object.assign(t, extra || {});
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

  // -- the traces of one state (always the same number, in the same order) ----------------
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

  function fmt(v) {
    if (v === null || !isFinite(v)) { return "n/a"; }
    var a = Math.abs(v);
    if (a === 0) { return "0"; }
    if (a < 1e-3 || a >= 1e6) { return v.toExponential(3); }
    return String(parseFloat(v.toPrecision(4)));
  }

  // an S or U centre or an end point of a leg: a marker is drawn there
  function onMarker(s, p) {
    return s.legs.some(function (leg) {
      var pts = [leg.A, leg.a];
      leg.joints.forEach(function (j) { if (j.k === "S" || j.k === "U") { pts.push(j.p); } });
      return pts.some(function (q) { return norm(sub(q, p)) <= 1e-6 * size; });
    });
  }

  // where each row's arrow goes at state s: null (nothing drawn) or its tail, head, unit
  // direction u and, for a couple, the point of its leg it is tied to
  function arrows(s) {
    var seen = {}, vmax = {};      // each kind scaled on its own at this pose, as screwkit draw
    D.rows.forEach(function (r, k) {
      var v = s.values[k];
      if (v !== null) { vmax[r.scale] = Math.max(vmax[r.scale] || 0, Math.abs(v)); }
    });
    return D.rows.map(function (r, k) {
      var leg = s.legs[r.leg], v = s.values[k], dir = s.directions[k];
      if (!leg || !dir || dir[0] === null) { return null; }
      var top = vmax[r.scale] || 0, ok = v !== null && top > 0;     // a 25 % floor
      var frac = ok ? Math.max(Math.abs(v) / top, 0.25) : 0.25;
      var vec = mul(dir, (ok && v < 0 ? -1 : 1) * frac * 0.6 * size), tail, tie = null;
      if (r.kind === "couple") {     // a free vector: beside its leg, tied to it by a dotted line
        var n = seen[r.leg] || 0;
        seen[r.leg] = n + 1;
        tie = add(leg.A, mul(sub(leg.a, leg.A), 0.5 + 0.12 * n));
        var side = cross(unit(sub(leg.a, leg.A)), dir);
        side = norm(side) < 1e-6 ? normal(sub(leg.a, leg.A)) : unit(side);
        tail = add(tie, mul(side, 0.22 * size));
      } else {                       // on its line, where the line passes nearest to a
        var q = s.points[k];
        tail = add(q, mul(dir, dot(sub(leg.a, q), dir)));
        if (!r.actuation && onMarker(s, tail)) {   // slide it clear of the ball it hides in
          tail = add(tail, mul(unit(vec), 0.06 * size));
        }
      }
      return {tail: tail, head: add(tail, vec), u: unit(vec), tie: tie, dir: dir};
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

  var labels = [];
  function wrenchTraces(s) {
    var out = [], geo = arrows(s), headLen = 0.09 * size;
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
      var text = s.text[k], pale = act ? 1.0 : 0.55;
      shaft.path([a.tail, sub(a.head, mul(a.u, 0.8 * headLen))], text);
      out.push(line(shaft, r.label, color, act ? 9 : 6,
                    {showlegend: false, legendgroup: group, hoverinfo: "text"}));
      out.push(cone(a.head, mul(a.u, headLen), color, pale, group));
      out.push(cone(sub(a.head, mul(a.u, 0.9 * headLen)), mul(a.u, couple ? headLen : 0), color,
                    couple ? pale : 0, group));
      labels.push({p: a.head, tail: a.tail, text: text, color: color});
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

  function traces(s) {
    labels = [];
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
      if (leg) { chain.path(leg.chain, lg.label); }
      out.push(line(chain, lg.label, lg.color, 7, {legendgroup: "leg" + i, opacity: 0.8,
                                                  line: {color: lg.color, width: 7,
                                                         dash: lg.passive ? "dash" : "solid"}}));
    });
    out = out.concat(jointTraces(s));
    var o = new Points();
    if (s.o) { o.add(s.o, "o (platform centre: the workload acts here)"); }
    out.push(markers(o, "o (where the workload acts)", "#252525", 5));
    out = out.concat(wrenchTraces(s));
    out.push(legendOnly("actuation force: thick shaft, full head", "#333333", "solid", 8, "kinds"));
    out.push(legendOnly("constraint force: thin shaft, pale head", "#888888", "solid", 4, "kinds"));
    out.push(legendOnly("couple: two heads, beside its leg", "#888888", "solid", 4, "kinds"));
    out.push(legendOnly("line of action of a force", "#555555", "dot", 2, "kinds"));
    return out;
  }

  // -- the labels: 3D annotations tied to their arrow heads, spread on the screen ----------
  // The screen positions come from an orthographic projection of the default camera; each
  // label takes, among 16 directions x 3 distances around its arrow head, the offset whose
  // box covers the fewest other labels and arrow heads, preferring the sides of its arrow.
  function projector() {
    var e = layout.scene.camera.eye, ar = layout.scene.aspectratio;
    var view = unit([-e.x, -e.y, -e.z]), right = unit(cross(view, [0, 0, 1]));
    var up = cross(right, view);
    var scale = [ar.x / (hi[0] - lo[0]), ar.y / (hi[1] - lo[1]), ar.z / (hi[2] - lo[2])];
    var mid = mul(add(lo, hi), 0.5);
    var px = 0.62 * Math.min(plot.clientWidth || 900, layout.height);
    return function (p) {
      var n = [(p[0] - mid[0]) * scale[0], (p[1] - mid[1]) * scale[1], (p[2] - mid[2]) * scale[2]];
      return [px * dot(n, right), -px * dot(n, up)];         // pixels, y downwards
    };
  }
  function placeLabels() {
    var proj = projector(), boxes = [], heads = labels.map(function (l) { return proj(l.p); });
    var out = [];
    labels.forEach(function (l, n) {
      var a = heads[n], t = proj(l.tail), d = unit([a[0] - t[0], a[1] - t[1], 0]);
      var w = 7.2 * l.text.length + 8, h = 18, best = null;
      for (var r = 0; r < 3; r++) {
        for (var q = 0; q < 16; q++) {
          var th = q * Math.PI / 8, dist = [30, 50, 75][r];
          var c = [a[0] + dist * Math.cos(th), a[1] + dist * Math.sin(th)];
          var box = [c[0] - w / 2, c[1] - h / 2, c[0] + w / 2, c[1] + h / 2], cost = dist / 30;
          boxes.forEach(function (b) {
            var ox = Math.min(box[2], b[2]) - Math.max(box[0], b[0]);
            var oy = Math.min(box[3], b[3]) - Math.max(box[1], b[1]);
            if (ox > 0 && oy > 0) { cost += 20 + ox * oy / (w * h) * 100; }
          });
          heads.forEach(function (hd, k) {
            if (hd[0] > box[0] - 6 && hd[0] < box[2] + 6 && hd[1] > box[1] - 6 && hd[1] < box[3] + 6) {
              cost += k === n ? 30 : 12;
            }
          });
          cost += 2 * Math.abs(Math.cos(th) * d[0] + Math.sin(th) * d[1]);  // beside, not ahead
          if (!best || cost < best.cost) { best = {cost: cost, box: box, ax: c[0] - a[0], ay: c[1] - a[1]}; }
        }
      }
      boxes.push(best.box);
      out.push({x: l.p[0], y: l.p[1], z: l.p[2], text: l.text, showarrow: true, arrowhead: 0,
                arrowwidth: 1, arrowcolor: l.color, ax: best.ax, ay: best.ay,
                font: {color: l.color, size: 12}, bgcolor: "rgba(255,255,255,0.85)",
                bordercolor: l.color, borderwidth: 1, borderpad: 2});
    });
    return out;
  }

  // -- the page around the plot ------------------------------------------------------------
  var lo = D.box.lo, hi = D.box.hi, span = Math.max(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]);
  function axis(k, name) {
    return {range: [lo[k], hi[k]], title: {text: name + " [" + U.length + "]"},
            backgroundcolor: "#fafafa", gridcolor: "#dddddd", zerolinecolor: "#bbbbbb"};
  }
  var layout = {
    uirevision: "screwkit", height: 700, margin: {l: 0, r: 0, t: 36, b: 0},
    title: {text: "", font: {size: 14}},
    legend: {x: 1.0, xanchor: "right", y: 1.0, bgcolor: "rgba(255,255,255,0.85)",
             bordercolor: "#cccccc", borderwidth: 1, font: {size: 11},
             groupclick: "togglegroup"},
    scene: {aspectmode: "manual",
            aspectratio: {x: (hi[0] - lo[0]) / span, y: (hi[1] - lo[1]) / span,
                          z: (hi[2] - lo[2]) / span},
            xaxis: axis(0, "x"), yaxis: axis(1, "y"), zaxis: axis(2, "z"),
            camera: {eye: {x: 1.85 * Math.cos(-1.05), y: 1.85 * Math.sin(-1.05), z: 0.9},
                     up: {x: 0, y: 0, z: 1}}}
  };
  var config = {displaylogo: false, responsive: true, showLink: false, showSendToCloud: false};

  function poseText(s) {
    return Object.keys(s.pose).map(function (k) {
      var ang = ["alpha", "beta", "gamma"].indexOf(k) >= 0;
      return k + " = " + fmt(s.pose[k]) + (ang ? "°" : " " + U.length);
    }).join(", ");
  }

  function status(s) {
    var el = document.getElementById("sk-status");
    var cond = s.condition_number === null ? "n/a" : fmt(s.condition_number);
    var msg = {ok: "regular", "ill-conditioned": "ill-conditioned",
               "near-singular": "near-singular (efforts large against the load)",
               singular: "SINGULAR: no statics (values n/a)",
               unreachable: "UNREACHABLE: the loops do not close (nothing drawn)"}[s.level] || s.level;
    el.innerHTML = "";
    var badge = document.createElement("span");
    badge.className = "sk-level sk-level-" + s.level.replace(/[^a-z]/g, "");
    badge.textContent = "singularity level: " + msg;
    el.appendChild(badge);
    var rest = document.createElement("span");
    rest.textContent = "  condition number " + cond + " · pose: " + poseText(s)
      + (s.notes.length ? " · " + s.notes.join("; ") : "");
    el.appendChild(rest);
    var rows = document.getElementById("sk-values");
    rows.innerHTML = "<tr><th>row</th><th>value</th></tr>";
    D.rows.forEach(function (r, k) {
      var tr = document.createElement("tr"), td1 = document.createElement("td"),
          td2 = document.createElement("td");
      td1.textContent = r.label + (r.actuation ? " (actuation)" : "");
      td1.style.color = D.legs[r.leg].color;
      td2.textContent = s.text[k].split(" = ")[1];
      td2.className = "sk-num";
      tr.appendChild(td1); tr.appendChild(td2); rows.appendChild(tr);
    });
  }

  function show(i) {
    current = i;
    var s = D.states[i];
    layout.title.text = D.title + " · " + poseText(s) + " · level " + s.level;
    var data = traces(s);
    layout.scene.annotations = placeLabels();
    Plotly.react(plot, data, layout, config);
    status(s);
  }

  // -- controls: a slider per grid parameter, or a time slider with play/pause -------------
  var controls = document.getElementById("sk-controls");
  var sliders = [], outputs = [];
  function cellOf(i) {            // the slider positions of state i (C order: last fastest)
    var ps = D.controls.params, cell = [];
    for (var n = ps.length - 1; n >= 0; n--) {
      cell[n] = i % ps[n].values.length; i = Math.floor(i / ps[n].values.length);
    }
    return cell;
  }
  function gridIndex() {
    var idx = 0;
    D.controls.params.forEach(function (p, n) {
      idx = idx * p.values.length + Number(sliders[n].value);
    });
    return idx;
  }
  function shownValues() {
    if (D.controls.type === "grid") {
      D.controls.params.forEach(function (p, n) {
        outputs[n].textContent = fmt(p.values[Number(sliders[n].value)]) + " " + p.unit;
      });
    } else if (sliders.length) {
      var t = D.controls.t, k = Number(sliders[0].value);
      outputs[0].textContent = "t = " + fmt(t[k]) + " (sample " + (k + 1) + " of " + t.length + ")";
    }
  }
  function select(i) {            // show state i and put the sliders there
    if (D.controls.type === "grid") {
      var cell = cellOf(i);
      sliders.forEach(function (el, n) { el.value = cell[n]; });
    } else if (sliders.length) {
      sliders[0].value = i;
    }
    shownValues();
    show(i);
  }
  function slider(id, max, text) {
    var box = document.createElement("label"), input = document.createElement("input"),
        out = document.createElement("output");
    input.type = "range"; input.min = 0; input.max = max; input.step = 1; input.id = id;
    box.appendChild(document.createTextNode(text + " "));
    box.appendChild(input); box.appendChild(out); controls.appendChild(box);
    sliders.push(input); outputs.push(out);
    return {box: box, input: input};
  }
  if (D.controls.type === "grid") {
    D.controls.params.forEach(function (p) {
      var el = slider("sk-slider-" + p.name, p.values.length - 1, p.name);
      el.input.addEventListener("input", function () { shownValues(); show(gridIndex()); });
    });
  } else if (D.states.length > 1) {
    var el = slider("sk-slider-t", D.states.length - 1, "time"), timer = null;
    var button = document.createElement("button");
    button.id = "sk-play"; button.textContent = "play";
    el.box.insertBefore(button, el.box.firstChild);
    el.input.addEventListener("input", function () { shownValues(); show(Number(el.input.value)); });
    button.addEventListener("click", function () {
      if (timer) { clearInterval(timer); timer = null; button.textContent = "play"; return; }
      button.textContent = "pause";
      timer = setInterval(function () {
        select((Number(el.input.value) + 1) % D.states.length);
      }, Math.max(60, Math.min(250, 8000 / D.states.length)));
    });
  }

  document.getElementById("sk-title").textContent = D.title;
  document.getElementById("sk-workload").textContent = "workload: " + D.workload.text;
  document.getElementById("sk-notes").textContent = D.notes.join(" ");
  window.screwkitView = {data: D, state: function () { return current; }, show: select};
  select(current);
})();
