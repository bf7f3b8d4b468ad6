/* screwkit's 3D view, part 3 of 3: the page around the plot (workload, singularity level,
 * values, the arrows' scale) and the controls: a slider per grid parameter, or a time slider
 * with play/pause.  window.screwkitView exposes the data, the state shown, show(i) and the
 * arrows drawn (the tests read them). */
var current = D.start;
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

function scaleText(s) {
  if (!D.rows.length || !s.legs.length) { return ""; }
  if (D.workload.force === null) {
    return "no workload: every wrench drawn on its line at one length, its direction that of "
      + "its row of J (no value)";
  }
  var low = D.rows.filter(function (r, k) { return s.floored[k]; })
    .map(function (r) { return r.label; });
  return "arrow lengths proportional to |value| within each kind at this pose (actuation "
    + "forces, constraint forces, torques)" + (low.length ? "; drawn at " + (100 * D.floor)
    + " % of the largest of its kind (value below that, zero or n/a): " + low.join(", ") : "");
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
  document.getElementById("sk-scale").textContent = scaleText(s);
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

// draw state s: its arrows and labels placed for the camera's projection proj
var draws = 0;           // how many times the plot was drawn (the tests wait on it)
var ready = false;       // drawn for plotly's own camera (screenshots wait for it)
function draw(s, proj) {
  draws += 1;
  var geo = arrows(s, proj);
  layout.scene.annotations = placeLabels(s, geo, proj);
  return Plotly.react(plot, traces(s, geo), layout, config);
}
var drawn = false;
function redraw() {              // plotly's camera moved (or exists now): place again for it
  var proj = sceneProjector();
  if (proj) { draw(D.states[current], proj); }
}
function show(i) {
  current = i;
  var s = D.states[i];
  layout.title.text = D.title + " · " + poseText(s) + " · level " + s.level;
  var first = !drawn;
  drawn = true;
  var done = draw(s, sceneProjector() || estimateProjector());
  if (first && done && done.then) {       // now that plotly's camera exists: its projection
    done.then(function () { redraw(); ready = true; });
    plot.on("plotly_relayout", function (ev) {   // the user turned or zoomed the view
      // (plotly's camera matrices follow on its next frame)
      if (Object.keys(ev || {}).some(function (k) { return k.indexOf("scene.camera") === 0; })) {
        setTimeout(redraw, 60);
      }
    });
  }
  status(s);
}

// -- controls: a slider per grid parameter, or a time slider with play/pause ---------------
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
window.screwkitView = {
  data: D, state: function () { return current; }, show: select,
  draws: function () { return draws; }, ready: function () { return ready; },
  // the arrows of state i as drawn: [{label, tail, head}] (null where none is drawn)
  arrows: function (i) {
    var proj = sceneProjector() || estimateProjector();
    return arrows(D.states[i === undefined ? current : i], proj).map(function (a, k) {
      return a && {label: D.rows[k].label, tail: a.tail, head: a.head};
    });
  }
};
select(current);
