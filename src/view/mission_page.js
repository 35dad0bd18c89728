// uavip mission page (view/mission_page.h): draws the data block #uavip-data with
// three.js r111. Local ENU metres, z up; positions arrive quantised to 16 bits per
// axis over the box (box_min, box_size) and are drawn relative to the box centre.
// Sets document.title to "ready" once drawn, or to "error: ..." (tests read it).
(function () {
  'use strict';

  function fail(e) {
    var msg = 'error: ' + (e && e.message ? e.message : String(e));
    document.title = msg;
    var s = document.getElementById('status');
    if (s) s.textContent = msg;
  }
  window.addEventListener('error', function (ev) { fail(ev.message || ev); });

  // ---- decoding
  function bytes(s) {
    var bin = atob(s), n = bin.length, u = new Uint8Array(n);
    for (var i = 0; i < n; i++) u[i] = bin.charCodeAt(i);
    return u;
  }
  function u16(s) { var b = bytes(s); return new Uint16Array(b.buffer, 0, b.length >> 1); }
  function u32(s) { var b = bytes(s); return new Uint32Array(b.buffer, 0, b.length >> 2); }
  function f32(s) { var b = bytes(s); return new Float32Array(b.buffer, 0, b.length >> 2); }
  function f64(s) { var b = bytes(s); return new Float64Array(b.buffer, 0, b.length >> 3); }
  function rgb(hex) {
    var v = parseInt(hex.slice(1), 16);
    return [(v >> 16) & 255, (v >> 8) & 255, v & 255];
  }
  function fmt(v, d) { return Number(v).toFixed(d); }

  var D, origin, scale;  // data; box centre [m]; metres per quantum per axis
  function positions(s) {  // Float32Array xyz relative to the box centre
    var q = u16(s), out = new Float32Array(q.length);
    for (var i = 0; i < q.length; i += 3) {
      out[i] = q[i] * scale[0] - origin[0] + D.box_min[0];
      out[i + 1] = q[i + 1] * scale[1] - origin[1] + D.box_min[1];
      out[i + 2] = q[i + 2] * scale[2] - origin[2] + D.box_min[2];
    }
    return out;
  }

  var renderer, scene, camera, controls, viewEl, labelsEl;
  var layers = {}, layerBoxes = {};
  var cloudSets = [];        // {name, pos (Float32Array), obj}
  var stops = {};            // decoded photo stops
  var pathObjs = [];         // {label, color, samples, clearance, line, arrows, entries}
  var labelItems = [];       // {el, p (THREE.Vector3), layer}
  var pathMode = 'clearance';
  var diag = 1, spacing = 0.05, baseSpacing = 0.05, frustumLen = 1;
  var picked = [];           // shift-clicked cloud points
  var pickObj = null, measureObj = null;
  var currentView = 'orbit', userMoved = false;

  var phases = {};  // performance.now() at the steps to ready [ms], published as data-phase-ms
  function main() {
    phases.script = performance.now();
    D = JSON.parse(document.getElementById('uavip-data').textContent);
    phases.parsed = performance.now();
    if (typeof THREE === 'undefined' || !THREE.OrbitControls) throw new Error('three.js is missing from the page');
    document.getElementById('heading').textContent = D.title;
    document.getElementById('summary').textContent = D.summary_line;
    scale = [D.box_size[0] / 65535, D.box_size[1] / 65535, D.box_size[2] / 65535];
    origin = [D.box_min[0] + D.box_size[0] / 2, D.box_min[1] + D.box_size[1] / 2, D.box_min[2] + D.box_size[2] / 2];
    diag = Math.sqrt(D.box_size[0] * D.box_size[0] + D.box_size[1] * D.box_size[1] + D.box_size[2] * D.box_size[2]);

    viewEl = document.getElementById('view');
    labelsEl = document.getElementById('labels');
    renderer = new THREE.WebGLRenderer({ antialias: false, preserveDrawingBuffer: true });
    renderer.setPixelRatio(1);
    renderer.setClearColor(0xffffff, 1);
    viewEl.insertBefore(renderer.domElement, viewEl.firstChild);
    scene = new THREE.Scene();
    camera = new THREE.OrthographicCamera(-1, 1, 1, -1, -100 * diag, 100 * diag);
    camera.up.set(0, 0, 1);
    controls = new THREE.OrbitControls(camera, renderer.domElement);
    controls.screenSpacePanning = true;
    controls.addEventListener('change', requestDraw);

    buildCloud();
    buildBoundaries();
    buildStops();
    buildPaths();
    buildHome();
    buildFleet();
    buildUi();
    buildFleetUi();
    phases.built = performance.now();
    resize();
    controls.addEventListener('start', function () { userMoved = true; });
    window.addEventListener('resize', function () {
      resize();
      if (!userMoved) setView(currentView);  // a window resized before any drag: fit again
      requestDraw();
    });
    window.addEventListener('hashchange', function () { applyHash(); requestDraw(); });
    renderer.domElement.addEventListener('pointerdown', onDown);
    renderer.domElement.addEventListener('pointerup', onUp);
    applyHash();
    draw();
    phases.first_frame = performance.now();
    finishReady();
    exposeForEditing();
  }

  // What the edit mode (mission_edit.js, a script of its own) may use of the page.
  function exposeForEditing() {
    window.uavipPage = {
      data: D, origin: origin, scene: scene, camera: camera, controls: controls,
      canvas: renderer.domElement, requestDraw: requestDraw, addToLayer: addToLayer
    };
  }

  // ---- layers
  function addToLayer(name, obj) {
    (layers[name] = layers[name] || []).push(obj);
    scene.add(obj);
  }
  function setLayer(name, on) {
    (layers[name] || []).forEach(function (o) { o.visible = on; });
    if (layerBoxes[name]) layerBoxes[name].checked = on;
    labelItems.forEach(function (l) { if (l.layer === name) l.on = on; });
  }
  function layerOn(name) { return layerBoxes[name] ? layerBoxes[name].checked : true; }

  // ---- the cloud: one Points object per class
  function pointMaterial() {
    return new THREE.PointsMaterial({ size: 2, sizeAttenuation: false, vertexColors: THREE.VertexColors });
  }
  var kDrawnPoints = 40000, cloudStride = 1, allPoints = false;
  function setAllPoints(on) {
    allPoints = on;
    cloudSets.forEach(function (c) { c.obj.geometry.setDrawRange(0, on ? c.n : c.prefix); });
  }
  function drawnPoints() { return cloudSets.reduce(function (a, c) { return a + (allPoints ? c.n : c.prefix); }, 0); }
  function buildCloud() {
    var c = D.cloud, all = positions(c.pos), cls = bytes(c.cls), sid = u16(c.sid);
    var surfCol = D.surfaces.map(function (s) { return rgb(s.color); });
    var other = rgb(D.colors.other), obst = rgb(D.colors.obstacle);
    var names = ['cloud-other', 'cloud-surfaces', 'cloud-obstacles'];
    // Points in interleaved order (every K-th first, then the next offset, ...), so the
    // first 1/K of each class is an even subsample: the page draws that prefix (about
    // kDrawnPoints points, what a software renderer draws in a frame) unless the user
    // asks for every point.
    cloudStride = Math.max(1, Math.ceil(c.n / kDrawnPoints));
    for (var k = 0; k < 3; k++) {
      var n = c.by_class[k];
      var pos = new Float32Array(3 * n), col = new Uint8Array(3 * n), j = 0, prefix = 0;
      for (var r = 0; r < cloudStride; r++) {
        for (var i = r; i < c.n; i += cloudStride) {
          if (cls[i] !== k) continue;
          pos[3 * j] = all[3 * i]; pos[3 * j + 1] = all[3 * i + 1]; pos[3 * j + 2] = all[3 * i + 2];
          var rgbv = k === 0 ? other : k === 2 ? obst : (surfCol[sid[i]] || other);
          col[3 * j] = rgbv[0]; col[3 * j + 1] = rgbv[1]; col[3 * j + 2] = rgbv[2];
          j++;
        }
        if (r === 0) prefix = j;
      }
      var g = new THREE.BufferGeometry();
      g.setAttribute('position', new THREE.BufferAttribute(pos, 3));
      g.setAttribute('color', new THREE.BufferAttribute(col, 3, true));
      var obj = new THREE.Points(g, pointMaterial());
      cloudSets.push({ name: names[k], pos: pos, obj: obj, n: n, prefix: prefix });
      addToLayer(names[k], obj);
    }
    setAllPoints(false);
    // The point spacing: measured, else from the surfaces' area per point.
    // The spacing of the drawn points: the larger of the measured one and the surfaces'
    // area per point (median), times the square root of the decimation stride.
    var v = D.surfaces.filter(function (s) { return s.points > 0; })
      .map(function (s) { return Math.sqrt(s.area_m2 / s.points); }).sort(function (a, b) { return a - b; });
    spacing = Math.max(D.spacing_m || 0, v.length ? v[v.length >> 1] : 0);
    if (!(spacing > 0)) spacing = diag / 1000;
    spacing *= Math.sqrt(c.stride || 1);
    baseSpacing = spacing;
  }

  // ---- surface boundaries and their labels
  function buildBoundaries() {
    D.surfaces.forEach(function (s) {
      if (s.boundary_n < 2) return;
      var p = positions(s.boundary), g = new THREE.BufferGeometry();
      g.setAttribute('position', new THREE.BufferAttribute(p, 3));
      var mat = new THREE.LineBasicMaterial({ color: new THREE.Color(s.color).multiplyScalar(0.6) });
      addToLayer('boundaries', new THREE.LineLoop(g, mat));
      (s.holes || []).forEach(function (h) {  // openings (a window) in the outline
        var hg = new THREE.BufferGeometry();
        hg.setAttribute('position', new THREE.BufferAttribute(positions(h), 3));
        addToLayer('boundaries', new THREE.LineLoop(hg, mat));
      });
      var c = s.centroid;
      addLabel('surface ' + s.id + ' \u00b7 ' + s.status, new THREE.Vector3(c[0] - origin[0], c[1] - origin[1], c[2] - origin[2]),
        'labels', s.color, s.reason);
    });
  }
  function addLabel(text, p, layer, color, title) {
    var el = document.createElement('div');
    el.className = 'lbl';
    el.textContent = text;
    if (color) el.style.color = color;
    if (title) el.title = title;
    labelsEl.appendChild(el);
    labelItems.push({ el: el, p: p, layer: layer, on: true });
  }

  // ---- photo stops as frusta: apex at the UAV, opening toward where the camera looks
  function lookDir(yawDeg, pitchDeg) {
    var y = yawDeg * Math.PI / 180, p = pitchDeg * Math.PI / 180;
    return new THREE.Vector3(Math.cos(p) * Math.cos(y), Math.cos(p) * Math.sin(y), Math.sin(p));
  }
  function buildStops() {
    var S = D.stops;
    stops.n = S.n;
    stops.pos = positions(S.pos);
    stops.target = positions(S.target);
    stops.angles = f32(S.angles);
    stops.mission = u16(S.mission);
    stops.index = u32(S.index);
    stops.flown = bytes(S.flown);
    if (!S.n) return;
    // Frustum depth: 0.4 x the smallest photo spacing, within [diag/400, diag/40].
    var minSpacing = Infinity;
    D.missions.forEach(function (m) {
      if (m.camera && m.camera.spacing_m) m.camera.spacing_m.forEach(function (v) { if (v > 0) minSpacing = Math.min(minSpacing, v); });
    });
    frustumLen = Math.min(Math.max(isFinite(minSpacing) ? 0.4 * minSpacing : diag / 60, diag / 400), diag / 40);
    // Four edges from the camera to the corners, and the rim unless there are many
    // (the rim doubles the vertices a frame draws).
    var rim = S.n <= 3000, edges = rim ? 8 : 4;
    var pos = new Float32Array(S.n * edges * 2 * 3), col = new Uint8Array(S.n * edges * 2 * 3), o = 0;
    var a = new THREE.Vector3(), d = new THREE.Vector3(), r = new THREE.Vector3(), u = new THREE.Vector3();
    var corners = [new THREE.Vector3(), new THREE.Vector3(), new THREE.Vector3(), new THREE.Vector3()];
    function put(v, c) { pos[o] = v.x; pos[o + 1] = v.y; pos[o + 2] = v.z; col[o] = c[0]; col[o + 1] = c[1]; col[o + 2] = c[2]; o += 3; }
    for (var i = 0; i < S.n; i++) {
      var m = D.missions[stops.mission[i]] || {};
      var c = stops.flown[i] ? rgb(m.color || '#888888') : [150, 150, 150];
      var ratioW = 0.6, ratioH = 0.45;
      if (m.camera && m.camera.footprint_m && m.camera.standoff_m > 0) {
        ratioW = m.camera.footprint_m[0] / 2 / m.camera.standoff_m;
        ratioH = m.camera.footprint_m[1] / 2 / m.camera.standoff_m;
      }
      a.set(stops.pos[3 * i], stops.pos[3 * i + 1], stops.pos[3 * i + 2]);
      d.copy(lookDir(stops.angles[2 * i], stops.angles[2 * i + 1]));
      r.set(Math.sin(stops.angles[2 * i] * Math.PI / 180), -Math.cos(stops.angles[2 * i] * Math.PI / 180), 0);
      u.crossVectors(r, d).normalize();
      var w = frustumLen * ratioW, h = frustumLen * ratioH;
      for (var k = 0; k < 4; k++) {
        corners[k].copy(a).addScaledVector(d, frustumLen)
          .addScaledVector(r, (k === 1 || k === 2) ? w : -w).addScaledVector(u, k >= 2 ? h : -h);
      }
      for (k = 0; k < 4; k++) { put(a, c); put(corners[k], c); }
      if (rim) for (k = 0; k < 4; k++) { put(corners[k], c); put(corners[(k + 1) % 4], c); }
    }
    var g = new THREE.BufferGeometry();
    g.setAttribute('position', new THREE.BufferAttribute(pos, 3));
    g.setAttribute('color', new THREE.BufferAttribute(col, 3, true));
    addToLayer('photos', new THREE.LineSegments(g, new THREE.LineBasicMaterial({ vertexColors: THREE.VertexColors })));
  }

  // ---- the flight: one line per sortie (or per surface), order arrows and numbers
  function clearanceColor(cm) {
    var r = D.inflation_radius_m > 0 ? D.inflation_radius_m : 1.0, c = cm / 100;
    if (c < r) return [200, 0, 200];                  // closer than the clearance
    var t = Math.min((c - r) / (2 * r), 1);           // r .. 3r: red -> yellow -> green
    if (t < 0.5) return [220, Math.round(40 + 380 * t), 30];
    return [Math.round(220 - 400 * (t - 0.5)), Math.round(230 - 60 * (t - 0.5)), 30];
  }
  function buildPaths() {
    var number = 0, uavNumber = {};
    if (D.fleet) pathMode = 'sortie';  // a fleet: each UAV in its colour
    D.paths.forEach(function (P, pi) {
      var s = positions(P.samples), cl = u16(P.clearance_cm), wp = positions(P.waypoints);
      var g = new THREE.BufferGeometry();
      g.setAttribute('position', new THREE.BufferAttribute(s, 3));
      g.setAttribute('color', new THREE.BufferAttribute(new Uint8Array(s.length), 3, true));
      var line = new THREE.Line(g, new THREE.LineBasicMaterial({ vertexColors: THREE.VertexColors, depthTest: false }));
      line.renderOrder = 10;
      var name = 'path' + pi;
      addToLayer(name, line);
      (layers.flight = layers.flight || []).push(line);
      // Chevrons every diag/25 m along the path, pointing the way flown.
      var every = diag / 25, size = diag / 120, run = every / 2, arr = [];
      var t = new THREE.Vector3(), n = new THREE.Vector3(), p = new THREE.Vector3(), z = new THREE.Vector3(0, 0, 1);
      for (var i = 3; i < s.length; i += 3) {
        t.set(s[i] - s[i - 3], s[i + 1] - s[i - 2], s[i + 2] - s[i - 1]);
        var len = t.length();
        run += len;
        if (run < every || len === 0) continue;
        run = 0;
        t.normalize();
        n.crossVectors(t, z);
        if (n.length() < 0.3) n.set(1, 0, 0);
        n.normalize();
        p.set(s[i], s[i + 1], s[i + 2]);
        for (var side = -1; side <= 1; side += 2) {
          arr.push(p.x, p.y, p.z);
          arr.push(p.x - t.x * size + n.x * side * size * 0.6, p.y - t.y * size + n.y * side * size * 0.6,
            p.z - t.z * size + n.z * side * size * 0.6);
        }
      }
      var ag = new THREE.BufferGeometry();
      ag.setAttribute('position', new THREE.BufferAttribute(new Float32Array(arr), 3));
      var arrows = new THREE.LineSegments(ag, new THREE.LineBasicMaterial({ color: P.color, depthTest: false }));
      arrows.renderOrder = 11;
      addToLayer('order', arrows);
      P.entries.forEach(function (e) {
        var w = e[0], text = D.flown ? String(++number) : 'start ' + e[1];
        if (P.uav) {  // a fleet: surfaces numbered per UAV, "2.3" = UAV 2's third
          uavNumber[P.uav] = (uavNumber[P.uav] || 0) + 1;
          text = P.uav + '.' + uavNumber[P.uav];
        }
        addLabel(text, new THREE.Vector3(wp[3 * w], wp[3 * w + 1], wp[3 * w + 2]),
          'order', P.color, 'surface ' + e[1] + ' entered (' + P.label + ')');
      });
      pathObjs.push({ label: P.label, color: P.color, clearance: cl, line: line, name: name });
    });
    colourPaths();
  }
  function colourPaths() {
    pathObjs.forEach(function (P) {
      var col = P.line.geometry.attributes.color, a = col.array, c0 = rgb(P.color);
      for (var i = 0; i < P.clearance.length; i++) {
        var c = pathMode === 'clearance' ? clearanceColor(P.clearance[i]) : c0;
        a[3 * i] = c[0]; a[3 * i + 1] = c[1]; a[3 * i + 2] = c[2];
      }
      col.needsUpdate = true;
    });
  }
  function buildHome() {
    if (D.fleet) {  // each UAV's home in its colour
      D.fleet.uavs.forEach(function (u) {
        var hg = new THREE.BufferGeometry(), hp = new Float32Array([u.home[0] - origin[0], u.home[1] - origin[1], u.home[2] - origin[2]]);
        hg.setAttribute('position', new THREE.BufferAttribute(hp, 3));
        var ho = new THREE.Points(hg, new THREE.PointsMaterial({ size: 11, sizeAttenuation: false, color: new THREE.Color(u.color), depthTest: false }));
        ho.renderOrder = 12;
        addToLayer('home', ho);
        addLabel('home ' + u.uav, new THREE.Vector3(hp[0], hp[1], hp[2] + diag / 60), 'home', u.color, 'UAV ' + u.uav + ' takes off and lands here');
      });
      return;
    }
    var h = D.flight && D.flight.home;
    if (!h) return;
    var g = new THREE.BufferGeometry();
    var p = new Float32Array([h[0] - origin[0], h[1] - origin[1], h[2] - origin[2]]);
    g.setAttribute('position', new THREE.BufferAttribute(p, 3));
    var m = new THREE.PointsMaterial({ size: 11, sizeAttenuation: false, color: 0x000000, depthTest: false });
    var obj = new THREE.Points(g, m);
    obj.renderOrder = 12;
    addToLayer('home', obj);
    addLabel('home', new THREE.Vector3(p[0], p[1], p[2] + diag / 60), 'home', '#000000', D.flight.home_source || '');
  }

  // ---- the fleet (D.fleet): every UAV's motion over the schedule, a time slider that
  // replays it, and the closest approach between two airborne UAVs up to the slider's
  // time. Motion: pieces (t0, t1, a, b) at constant velocity, a UAV on the ground at its
  // home outside them (planning/fleet_types.h). The closest approach of two pieces is
  // exact: their difference moves linearly, so its squared length is a quadratic in t.
  var fleet = null;  // {uavs: [{uav, color, home (page), p: Float64Array}], spans, byEnd, pairs, t}
  function buildFleet() {
    if (!D.fleet) return;
    var off = [D.box_min[0] - origin[0], D.box_min[1] - origin[1], D.box_min[2] - origin[2]];
    fleet = { uavs: [], spans: [], pairs: [], t: 0, end: D.fleet.makespan_s || 0 };
    D.fleet.uavs.forEach(function (u) {
      var p = f64(u.pieces);
      for (var i = 0; i < p.length; i += 8) {
        for (var a = 0; a < 3; a++) { p[i + 2 + a] += off[a]; p[i + 5 + a] += off[a]; }
        fleet.end = Math.max(fleet.end, p[i + 1]);
      }
      fleet.uavs.push({ uav: u.uav, color: u.color, p: p, n: p.length / 8,
        home: [u.home[0] - origin[0], u.home[1] - origin[1], u.home[2] - origin[2]] });
    });
    // Spans: each time two UAVs are airborne on two pieces at once, with the start
    // separation d0 (b − a at lo) and relative velocity v; per pair in time order.
    var U = fleet.uavs;
    for (var a = 0; a < U.length; a++) {
      for (var b = a + 1; b < U.length; b++) {
        var list = [], P = U[a].p, Q = U[b].p, i = 0, j = 0;
        while (i < U[a].n && j < U[b].n) {
          var lo = Math.max(P[8 * i], Q[8 * j]), hi = Math.min(P[8 * i + 1], Q[8 * j + 1]);
          if (lo <= hi) {
            var pa = pieceAt(P, i, lo), qb = pieceAt(Q, j, lo), va = pieceVel(P, i), vb = pieceVel(Q, j);
            var sp = { lo: lo, hi: hi, a: a, b: b, d0: [qb[0] - pa[0], qb[1] - pa[1], qb[2] - pa[2]],
              v: [vb[0] - va[0], vb[1] - va[1], vb[2] - va[2]] };
            var m = spanMin(sp, hi);
            sp.min = m[0]; sp.tmin = m[1];
            list.push(sp);
            fleet.spans.push(sp);
          }
          if (P[8 * i + 1] <= Q[8 * j + 1]) i++; else j++;
        }
        fleet.pairs.push(list);
      }
    }
    // Spans by end time with a running minimum: those ended by T in one binary search.
    fleet.byEnd = fleet.spans.slice().sort(function (x, y) { return x.hi - y.hi; });
    var best = null;
    fleet.prefix = fleet.byEnd.map(function (sp) {
      if (!best || sp.min < best.min || (sp.min === best.min && sp.tmin < best.tmin)) best = sp;
      return best;
    });
    // Markers: one point per UAV; a line between the closest pair so far.
    var g = new THREE.BufferGeometry();
    g.setAttribute('position', new THREE.BufferAttribute(new Float32Array(3 * U.length), 3));
    g.setAttribute('color', new THREE.BufferAttribute(new Uint8Array(3 * U.length), 3, true));
    fleet.markers = new THREE.Points(g, new THREE.PointsMaterial({ size: 14, sizeAttenuation: false,
      vertexColors: THREE.VertexColors, depthTest: false }));
    fleet.markers.renderOrder = 15;
    addToLayer('fleet', fleet.markers);
    var lg = new THREE.BufferGeometry();
    lg.setAttribute('position', new THREE.BufferAttribute(new Float32Array(6), 3));
    fleet.link = new THREE.LineSegments(lg, new THREE.LineBasicMaterial({ color: 0xff0000, depthTest: false }));
    fleet.link.renderOrder = 16;
    addToLayer('fleet', fleet.link);
  }
  function pieceAt(P, i, t) {  // position on piece i at t (clamped)
    var o = 8 * i, t0 = P[o], t1 = P[o + 1], s = t1 > t0 ? Math.min(Math.max((t - t0) / (t1 - t0), 0), 1) : 0;
    return [P[o + 2] + s * (P[o + 5] - P[o + 2]), P[o + 3] + s * (P[o + 6] - P[o + 3]), P[o + 4] + s * (P[o + 7] - P[o + 4])];
  }
  function pieceVel(P, i) {
    var o = 8 * i, dt = P[o + 1] - P[o];
    return dt > 0 ? [(P[o + 5] - P[o + 2]) / dt, (P[o + 6] - P[o + 3]) / dt, (P[o + 7] - P[o + 4]) / dt] : [0, 0, 0];
  }
  function spanMin(sp, upTo) {  // [distance, time] least over [lo, min(hi, upTo)]
    var hi = Math.min(sp.hi, upTo), d = sp.d0, v = sp.v, vv = v[0] * v[0] + v[1] * v[1] + v[2] * v[2], t = sp.lo;
    if (vv > 0) t = Math.min(Math.max(sp.lo - (d[0] * v[0] + d[1] * v[1] + d[2] * v[2]) / vv, sp.lo), hi);
    var s = t - sp.lo, x = d[0] + s * v[0], y = d[1] + s * v[1], z = d[2] + s * v[2];
    return [Math.sqrt(x * x + y * y + z * z), t];
  }
  function uavAt(u, t) {  // {p (page), air, sortie (1-based, 0 on the ground)}
    var P = u.p, lo = 0, hi = u.n - 1, k = -1;
    while (lo <= hi) { var mid = (lo + hi) >> 1; if (P[8 * mid] <= t) { k = mid; lo = mid + 1; } else hi = mid - 1; }
    if (k >= 0 && t <= P[8 * k + 1]) return { p: pieceAt(P, k, t), air: true };
    return { p: u.home.slice(), air: false };
  }
  function closestSoFar(T) {  // {d, a, b, t} or null: the least over every span up to T
    var lo = 0, hi = fleet.byEnd.length - 1, k = -1, best = null;
    while (lo <= hi) { var mid = (lo + hi) >> 1; if (fleet.byEnd[mid].hi <= T) { k = mid; lo = mid + 1; } else hi = mid - 1; }
    if (k >= 0) { var b = fleet.prefix[k]; best = { d: b.min, a: b.a, b: b.b, t: b.tmin }; }
    fleet.pairs.forEach(function (list) {  // the span of each pair going on at T
      var l = 0, h = list.length - 1, j = -1;
      while (l <= h) { var m = (l + h) >> 1; if (list[m].lo <= T) { j = m; l = m + 1; } else h = m - 1; }
      if (j < 0 || list[j].hi <= T) return;
      var r = spanMin(list[j], T);
      if (!best || r[0] < best.d || (r[0] === best.d && r[1] < best.t)) best = { d: r[0], a: list[j].a, b: list[j].b, t: r[1] };
    });
    return best;
  }
  function worldText(p) { return '(' + [p[0] + origin[0], p[1] + origin[1], p[2] + origin[2]].map(function (q) { return fmt(q, 2); }).join(', ') + ')'; }
  function setFleetTime(t) {
    if (!fleet) return;
    t = Math.min(Math.max(t, 0), fleet.end);
    fleet.t = t;
    var pos = fleet.markers.geometry.attributes.position, col = fleet.markers.geometry.attributes.color;
    var state = [], lines = [];
    fleet.uavs.forEach(function (u, i) {
      var s = uavAt(u, t), c = rgb(u.color);
      if (!s.air) c = [Math.round((c[0] + 255) / 2), Math.round((c[1] + 255) / 2), Math.round((c[2] + 255) / 2)];
      pos.array[3 * i] = s.p[0]; pos.array[3 * i + 1] = s.p[1]; pos.array[3 * i + 2] = s.p[2];
      col.array[3 * i] = c[0]; col.array[3 * i + 1] = c[1]; col.array[3 * i + 2] = c[2];
      var w = [s.p[0] + origin[0], s.p[1] + origin[1], s.p[2] + origin[2]];
      state.push(u.uav + ' ' + w.map(function (q) { return q.toFixed(4); }).join(' ') + ' ' + (s.air ? 1 : 0));
      lines.push('<div><span class="sw" style="background:' + u.color + '"></span>uav ' + u.uav + ': ' +
        (s.air ? 'flying at ' + worldText(s.p) : 'on the ground') + '</div>');
    });
    pos.needsUpdate = true;
    col.needsUpdate = true;
    var c = closestSoFar(t), el = document.getElementById('uavip-state');
    var lp = fleet.link.geometry.attributes.position;
    if (c) {
      var pa = uavAt(fleet.uavs[c.a], c.t).p, pb = uavAt(fleet.uavs[c.b], c.t).p;
      lp.array.set(pa.concat(pb));
      lp.needsUpdate = true;
      fleet.link.visible = layerOn('fleet');
    } else {
      fleet.link.visible = false;
    }
    el.setAttribute('data-fleet-t', t.toFixed(4));
    el.setAttribute('data-fleet-positions', state.join(';'));
    el.setAttribute('data-fleet-closest', c ? [c.d.toFixed(6), fleet.uavs[c.a].uav, fleet.uavs[c.b].uav, c.t.toFixed(4)].join(' ') : 'none');
    var box = document.getElementById('fleet-state');
    if (box) {
      document.getElementById('fleet-time').value = t;
      document.getElementById('fleet-clock').textContent = 't = ' + fmt(t, 1) + ' s of ' + fmt(fleet.end, 1) + ' s (' +
        fmt(t / 60, 1) + ' of ' + fmt(fleet.end / 60, 1) + ' min)';
      box.innerHTML = lines.join('');
      var sep = D.fleet.separation_m;
      document.getElementById('fleet-closest').textContent = c ?
        'closest approach so far: ' + fmt(c.d, 2) + ' m, uav ' + fleet.uavs[c.a].uav + ' and uav ' + fleet.uavs[c.b].uav +
        ' at t = ' + fmt(c.t, 1) + ' s' + (c.d < sep ? ' \u2014 closer than the separation ' + fmt(sep, 2) + ' m' : ' (separation ' + fmt(sep, 2) + ' m)') :
        'closest approach so far: no two UAVs in the air at once yet';
    }
  }
  var playing = null;
  function buildFleetUi() {
    if (!fleet) return;
    var anchor = document.getElementById('pick').previousElementSibling;  // the "Picked" heading
    var h = document.createElement('h2');
    h.textContent = 'Fleet schedule';
    var div = document.createElement('div');
    div.id = 'fleet';
    div.innerHTML = '<input type="range" id="fleet-time" min="0" max="' + fleet.end + '" step="any" value="0" style="width:100%">' +
      '<div><button id="fleet-play">play</button> <span id="fleet-clock"></span></div>' +
      '<div id="fleet-state"></div><div id="fleet-closest" style="margin-top:3px"></div>';
    anchor.parentNode.insertBefore(h, anchor);
    anchor.parentNode.insertBefore(div, anchor);
    var slider = document.getElementById('fleet-time');
    slider.addEventListener('input', function () { setFleetTime(+slider.value); requestDraw(); });
    var play = document.getElementById('fleet-play');
    play.addEventListener('click', function () {
      if (playing) { cancelAnimationFrame(playing); playing = null; play.textContent = 'play'; return; }
      if (fleet.t >= fleet.end) setFleetTime(0);
      play.textContent = 'pause';
      var last = performance.now();
      var step = function (now) {  // the whole schedule in one minute
        setFleetTime(fleet.t + (now - last) / 1000 * fleet.end / 60);
        last = now;
        draw();
        if (fleet.t >= fleet.end) { playing = null; play.textContent = 'play'; return; }
        playing = requestAnimationFrame(step);
      };
      playing = requestAnimationFrame(step);
    });
    setFleetTime(0);
  }

  // ---- side panel: layers, legends
  function checkbox(parent, name, text, swatch) {
    var l = document.createElement('label'), b = document.createElement('input');
    b.type = 'checkbox';
    b.checked = true;
    b.addEventListener('change', function () {
      setLayer(name, b.checked);
      if (name === 'flight' || /^path\d+$/.test(name)) syncPaths();
      requestDraw();
    });
    l.appendChild(b);
    if (swatch) {
      var s = document.createElement('span');
      s.className = 'sw';
      s.style.background = swatch;
      l.appendChild(s);
    }
    l.appendChild(document.createTextNode(text));
    parent.appendChild(l);
    layerBoxes[name] = b;
    return b;
  }
  function syncPaths() {
    var on = layerOn('flight');
    pathObjs.forEach(function (P) { P.line.visible = on && layerOn(P.name); });
  }
  function buildUi() {
    var L = document.getElementById('layers');
    checkbox(L, 'cloud-surfaces', 'cloud: surface points (' + D.cloud.by_class[1] + ')');
    checkbox(L, 'cloud-obstacles', 'cloud: obstacle points (' + D.cloud.by_class[2] + ')');
    checkbox(L, 'cloud-other', 'cloud: other points (' + D.cloud.by_class[0] + ')');
    if (cloudStride > 1) {
      var l = document.createElement('label'), b = document.createElement('input');
      b.type = 'checkbox';
      b.id = 'allpoints';
      b.addEventListener('change', function () { setAllPoints(b.checked); requestDraw(); });
      l.appendChild(b);
      l.appendChild(document.createTextNode('all ' + D.cloud.n + ' points (else ' + drawnPoints() + ')'));
      l.title = 'draws every stored cloud point; slower on a software renderer';
      L.appendChild(l);
    }
    checkbox(L, 'boundaries', 'surface boundaries');
    checkbox(L, 'labels', 'surface ids and status');
    checkbox(L, 'photos', 'photos (' + D.stops.n + ' frusta)');
    checkbox(L, 'flight', D.fleet ? 'fleet (' + D.fleet.uavs.length + ' UAVs, ' + D.paths.length + ' sorties)' :
      D.flown ? 'flight (' + D.paths.length + ' sorties)' : 'paths (' + D.paths.length + ')');
    checkbox(L, 'order', 'order (arrows, numbers)');
    if (D.fleet) checkbox(L, 'home', 'homes (' + D.fleet.uavs.length + ' UAVs)');
    else if (D.flight && D.flight.home) checkbox(L, 'home', 'home');
    if (D.fleet) checkbox(L, 'fleet', 'UAVs at the slider\'s time');

    var C = document.getElementById('legend-cloud'), html = '';
    D.surfaces.forEach(function (s) {
      html += '<span title="' + s.status + '" style="margin-right:6px;white-space:nowrap"><span class="sw" style="background:' +
        s.color + '"></span>' + s.id + '</span> ';
    });
    html += '<br><span class="sw" style="background:' + D.colors.obstacle + '"></span>obstacle ' +
      '<span class="sw" style="background:' + D.colors.other + '"></span>other';
    C.innerHTML = '<div>surfaces by id:</div>' + html;

    var P = document.getElementById('legend-path');
    var modes = document.createElement('div');
    ['clearance', 'sortie'].forEach(function (m) {
      var l = document.createElement('label'), b = document.createElement('input');
      b.type = 'radio';
      b.name = 'pathmode';
      b.value = m;
      b.id = 'mode-' + m;
      b.checked = m === pathMode;
      b.addEventListener('change', function () { pathMode = m; colourPaths(); legendPath(); requestDraw(); });
      l.appendChild(b);
      l.appendChild(document.createTextNode(m === 'clearance' ? 'colour by clearance to the cloud' :
        'colour by ' + (D.fleet ? 'UAV' : D.flown ? 'sortie' : 'surface')));
      modes.appendChild(l);
    });
    P.appendChild(modes);
    var list = document.createElement('div');
    list.id = 'pathlist';
    P.appendChild(list);
    pathObjs.forEach(function (p) { checkbox(list, p.name, p.label, p.color); });
    var ramp = document.createElement('div');
    ramp.id = 'rampbox';
    P.appendChild(ramp);
    legendPath();

    Array.prototype.forEach.call(document.querySelectorAll('button[data-view]'), function (b) {
      b.addEventListener('click', function () { setView(b.getAttribute('data-view')); requestDraw(); });
    });
  }
  function legendPath() {
    var box = document.getElementById('rampbox');
    if (pathMode !== 'clearance') { box.innerHTML = ''; return; }
    var r = D.inflation_radius_m > 0 ? D.inflation_radius_m : 1.0, stops = [], k;
    for (k = 0; k <= 10; k++) {
      var c = clearanceColor(100 * (r + 2 * r * k / 10));
      stops.push('rgb(' + c.join(',') + ') ' + (k * 10) + '%');
    }
    box.innerHTML = '<div id="ramp" style="background:linear-gradient(to right,' + stops.join(',') + ')"></div>' +
      '<div style="width:200px;display:flex;justify-content:space-between"><span>' + fmt(r, 2) + ' m</span><span>' +
      fmt(2 * r, 2) + '</span><span>\u2265 ' + fmt(3 * r, 2) + ' m</span></div>' +
      '<div><span class="sw" style="background:rgb(200,0,200)"></span>closer than ' + fmt(r, 2) + ' m' +
      (D.inflation_radius_m > 0 ? ' (the inflation radius)' : '') + '</div>';
  }

  // ---- views
  function corners() {
    var h = [D.box_size[0] / 2, D.box_size[1] / 2, D.box_size[2] / 2], out = [];
    for (var i = 0; i < 8; i++) out.push(new THREE.Vector3(i & 1 ? h[0] : -h[0], i & 2 ? h[1] : -h[1], i & 4 ? h[2] : -h[2]));
    return out;
  }
  function fitZoom() {
    camera.updateMatrixWorld();
    var inv = new THREE.Matrix4().getInverse(camera.matrixWorld), minU = Infinity, maxU = -Infinity, minV = Infinity, maxV = -Infinity;
    corners().forEach(function (c) {
      var q = c.clone().applyMatrix4(inv);
      minU = Math.min(minU, q.x); maxU = Math.max(maxU, q.x); minV = Math.min(minV, q.y); maxV = Math.max(maxV, q.y);
    });
    // Centre the box on screen, then zoom so that it fills 90 % of the view.
    var cu = (minU + maxU) / 2, cv = (minV + maxV) / 2;
    var shift = new THREE.Vector3(cu, cv, 0).applyQuaternion(camera.quaternion);
    camera.position.add(shift);
    controls.target.add(shift);
    var halfW = camera.right, halfH = camera.top;
    camera.zoom = 0.9 * Math.min(2 * halfW / Math.max(maxU - minU, 1e-6), 2 * halfH / Math.max(maxV - minV, 1e-6));
    camera.updateProjectionMatrix();
  }
  function setView(name) {
    var dirs = { top: [0, -1e-3, 1], front: [0, -1, 0], side: [1, 0, 0], orbit: [0.8, -1.1, 0.75] };
    if (name === 'fit') { fitZoom(); controls.update(); return; }
    if (!dirs[name]) name = 'orbit';
    currentView = name;
    var d = new THREE.Vector3().fromArray(dirs[name]).normalize();
    controls.target.set(0, 0, 0);
    camera.position.copy(d.multiplyScalar(2 * diag));
    camera.lookAt(controls.target);
    fitZoom();
    controls.update();
  }
  function hashParams() {
    var h = {};
    location.hash.replace(/^#/, '').split('&').forEach(function (kv) {
      var i = kv.indexOf('=');
      if (i > 0) h[decodeURIComponent(kv.slice(0, i))] = decodeURIComponent(kv.slice(i + 1));
    });
    return h;
  }
  function applyHash() {
    var h = hashParams();
    // canvas=WxH fixes the drawing's size in CSS pixels (screenshots and tests: the same
    // picture whatever the window).
    var m = /^(\d+)x(\d+)$/.exec(h.canvas || '');
    fixedSize = m ? [Math.max(+m[1], 1), Math.max(+m[2], 1)] : null;
    resize();
    if (h.points === 'all' || h.points === 'some') {
      setAllPoints(h.points === 'all');
      var ap = document.getElementById('allpoints');
      if (ap) ap.checked = allPoints;
    }
    if (h.path === 'sortie' || h.path === 'clearance') {
      pathMode = h.path;
      var r = document.getElementById('mode-' + h.path);
      if (r) r.checked = true;
      colourPaths();
      legendPath();
    }
    if (fleet && h.t !== undefined && isFinite(+h.t)) setFleetTime(+h.t);
    if (h.layers !== undefined) {
      var want = h.layers.split(',');
      var groups = { cloud: ['cloud-surfaces', 'cloud-obstacles', 'cloud-other'] };
      Object.keys(layerBoxes).forEach(function (name) {
        if (/^path\d+$/.test(name)) return;
        var on = want.indexOf(name) >= 0;
        Object.keys(groups).forEach(function (g) { if (want.indexOf(g) >= 0 && groups[g].indexOf(name) >= 0) on = true; });
        setLayer(name, on);
      });
      syncPaths();
    }
    setView(h.view || 'orbit');
  }

  // ---- drawing
  var pending = false;
  function requestDraw() {
    if (pending) return;
    pending = true;
    requestAnimationFrame(function () { pending = false; draw(); });
  }
  var fixedSize = null;
  function canvasSize() {
    return fixedSize || [Math.max(viewEl.clientWidth, 1), Math.max(viewEl.clientHeight, 1)];
  }
  function pxPerMetre() { return canvasSize()[1] * camera.zoom / (camera.top - camera.bottom); }
  function resize() {
    var wh = canvasSize(), w = wh[0], h = wh[1], a = w / h, half = diag;
    renderer.setSize(w, h);
    camera.left = -half * a; camera.right = half * a; camera.top = half; camera.bottom = -half;
    camera.updateProjectionMatrix();
  }
  function draw() {
    var ppm = pxPerMetre();
    var sp = baseSpacing * (allPoints ? 1 : Math.sqrt(cloudStride));
    // 1.2 spacings wide, within [1.5, 4] px: a software renderer pays for every pixel.
    var size = Math.min(Math.max(1.2 * sp * ppm, 1.5), 4);
    cloudSets.forEach(function (c) { c.obj.material.size = size; });
    renderer.render(scene, camera);
    overlays(ppm);
  }
  function overlays(ppm) {
    var wh = canvasSize(), w = wh[0], h = wh[1], v = new THREE.Vector3();
    labelItems.forEach(function (l) {
      v.copy(l.p).project(camera);
      var show = l.on && Math.abs(v.z) <= 1 && Math.abs(v.x) <= 1.05 && Math.abs(v.y) <= 1.05;
      l.el.style.display = show ? '' : 'none';
      if (show) { l.el.style.left = ((v.x + 1) / 2 * w) + 'px'; l.el.style.top = ((1 - v.y) / 2 * h) + 'px'; }
    });
    // Scale bar: a round length near 120 px.
    var m = 120 / ppm, p10 = Math.pow(10, Math.floor(Math.log10(m))), nice = p10;
    [1, 2, 5, 10].forEach(function (f) { if (f * p10 <= m) nice = f * p10; });
    document.getElementById('scalebar').style.width = (nice * ppm) + 'px';
    document.getElementById('scalelabel').textContent = (nice >= 1 ? nice : fmt(nice, 2)) + ' m';
    // North arrow: the screen direction of +y.
    var a = new THREE.Vector3(0, 0, 0).project(camera), b = new THREE.Vector3(0, diag / 10, 0).project(camera);
    var dx = (b.x - a.x) * w / 2, dy = -(b.y - a.y) * h / 2, len = Math.sqrt(dx * dx + dy * dy);
    var ang = Math.atan2(dx, -dy) * 180 / Math.PI;
    var arrow = document.getElementById('northarrow');
    arrow.setAttribute('transform', 'rotate(' + fmt(ang, 1) + ')');
    arrow.setAttribute('opacity', len > 0.2 * diag / 10 * ppm ? 1 : 0.3);
    publishState();
  }
  function publishState() {
    var s = document.getElementById('uavip-state'), r = renderer.domElement.getBoundingClientRect();
    camera.updateMatrixWorld();
    var m = new THREE.Matrix4().multiplyMatrices(camera.projectionMatrix, camera.matrixWorldInverse);
    s.setAttribute('data-view', currentView);
    s.setAttribute('data-origin', origin.join(' '));
    s.setAttribute('data-matrix', m.elements.map(function (x) { return x.toPrecision(9); }).join(' '));
    s.setAttribute('data-canvas', [r.left, r.top, r.width, r.height].join(' '));
    s.setAttribute('data-path-mode', pathMode);
    s.setAttribute('data-points-drawn', drawnPoints());
  }

  // ---- picking: a click on a frustum shows the photo; shift-click two cloud points
  var downAt = null;
  function onDown(ev) { downAt = [ev.clientX, ev.clientY]; }
  function onUp(ev) {
    if (!downAt || Math.abs(ev.clientX - downAt[0]) + Math.abs(ev.clientY - downAt[1]) > 4) return;
    var r = renderer.domElement.getBoundingClientRect(), x = ev.clientX - r.left, y = ev.clientY - r.top;
    if (ev.shiftKey) pickPoint(x, y); else pickPhoto(x, y);
    requestDraw();
  }
  function screenOf(px, py, pz, v, w, h) {
    v.set(px, py, pz).project(camera);
    return [(v.x + 1) / 2 * w, (1 - v.y) / 2 * h, v.z];
  }
  function pickPhoto(x, y) {
    if (!stops.n || !layerOn('photos')) return;
    var w = renderer.domElement.clientWidth, h = renderer.domElement.clientHeight, v = new THREE.Vector3();
    var best = -1, bestD = 14 * 14;
    for (var i = 0; i < stops.n; i++) {
      var d = lookDir(stops.angles[2 * i], stops.angles[2 * i + 1]);
      var px = stops.pos[3 * i] + d.x * frustumLen / 2, py = stops.pos[3 * i + 1] + d.y * frustumLen / 2;
      var pz = stops.pos[3 * i + 2] + d.z * frustumLen / 2;
      var s = screenOf(px, py, pz, v, w, h), dd = (s[0] - x) * (s[0] - x) + (s[1] - y) * (s[1] - y);
      if (dd < bestD) { bestD = dd; best = i; }
    }
    if (pickObj) { scene.remove(pickObj); pickObj = null; }
    if (best < 0) { document.getElementById('pick').textContent = 'No photo there.'; return; }
    var m = D.missions[stops.mission[best]] || {}, i3 = 3 * best;
    var P = [stops.pos[i3] + origin[0], stops.pos[i3 + 1] + origin[1], stops.pos[i3 + 2] + origin[2]];
    var T = [stops.target[i3] + origin[0], stops.target[i3 + 1] + origin[1], stops.target[i3 + 2] + origin[2]];
    var txt = 'photo ' + stops.index[best] + ' of surface ' + m.surface_id + ' (' + m.status + ')' +
      (stops.flown[best] ? '' : ', not flown') +
      '\nposition (' + P.map(function (q) { return fmt(q, 2); }).join(', ') + ') m' +
      '\nyaw ' + fmt(stops.angles[2 * best], 1) + '\u00b0 (CCW from east), gimbal pitch ' + fmt(stops.angles[2 * best + 1], 1) + '\u00b0' +
      '\nlooks at (' + T.map(function (q) { return fmt(q, 2); }).join(', ') + ') m';
    if (m.camera && m.camera.footprint_m) txt += '\ncovers ' + fmt(m.camera.footprint_m[0], 2) + ' \u00d7 ' + fmt(m.camera.footprint_m[1], 2) + ' m there';
    document.getElementById('pick').textContent = txt;
    var g = new THREE.BufferGeometry();
    g.setAttribute('position', new THREE.BufferAttribute(new Float32Array([stops.pos[i3], stops.pos[i3 + 1], stops.pos[i3 + 2],
      stops.target[i3], stops.target[i3 + 1], stops.target[i3 + 2]]), 3));
    pickObj = new THREE.LineSegments(g, new THREE.LineBasicMaterial({ color: 0x000000, depthTest: false }));
    pickObj.renderOrder = 13;
    scene.add(pickObj);
  }
  // ---- a picked point's WGS84 position (#uavip-geo: io::GeoFit, the scene's CRS as a
  // quadratic in local metres; the page has no PROJ)
  var GEO = (function () { var e = document.getElementById('uavip-geo'); return e ? JSON.parse(e.textContent) : null; })();
  function geoText(p) {
    if (!GEO) return '';
    var u = (p[0] - GEO.centre[0]) / GEO.half[0], v = (p[1] - GEO.centre[1]) / GEO.half[1], w = (p[2] - GEO.centre[2]) / GEO.half[2];
    var b = [1, u, v, w, u * u, v * v, w * w, u * v, u * w, v * w];
    var f = function (c) { var s = 0; for (var k = 0; k < 10; ++k) s += c[k] * b[k]; return s; };
    return '\n  lat ' + fmt(f(GEO.lat), 8) + '\u00b0, lon ' + fmt(f(GEO.lon), 8) + '\u00b0, h ' + fmt(f(GEO.h), 2) + ' m above the WGS84 ellipsoid';
  }
  function pickPoint(x, y) {
    var w = renderer.domElement.clientWidth, h = renderer.domElement.clientHeight, v = new THREE.Vector3();
    var best = null, bestD = 8 * 8, bestZ = Infinity;
    cloudSets.forEach(function (c) {
      if (!c.obj.visible) return;
      var end = 3 * (allPoints ? c.n : c.prefix);
      for (var i = 0; i < end; i += 3) {
        var s = screenOf(c.pos[i], c.pos[i + 1], c.pos[i + 2], v, w, h);
        var dd = (s[0] - x) * (s[0] - x) + (s[1] - y) * (s[1] - y);
        if (dd < bestD - 1 || (dd < bestD + 1 && s[2] < bestZ)) { bestD = dd; bestZ = s[2]; best = [c.pos[i], c.pos[i + 1], c.pos[i + 2]]; }
      }
    });
    if (!best) return;
    if (picked.length === 2) picked = [];
    picked.push(best);
    var world = function (p) { var l = [p[0] + origin[0], p[1] + origin[1], p[2] + origin[2]]; return '(' + l.map(function (q) { return fmt(q, 2); }).join(', ') + ')' + geoText(l); };
    var txt = 'point ' + world(picked[0]);
    if (measureObj) { scene.remove(measureObj); measureObj = null; }
    if (picked.length === 2) {
      var a = picked[0], b = picked[1], d = Math.sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) + (a[2] - b[2]) * (a[2] - b[2]));
      txt += '\npoint ' + world(b) + '\ndistance ' + fmt(d, 3) + ' m';
      var g = new THREE.BufferGeometry();
      g.setAttribute('position', new THREE.BufferAttribute(new Float32Array(a.concat(b)), 3));
      measureObj = new THREE.Line(g, new THREE.LineBasicMaterial({ color: 0xff0000, depthTest: false }));
      measureObj.renderOrder = 14;
      scene.add(measureObj);
    } else {
      txt += '\nshift-click a second point for the distance';
    }
    document.getElementById('pick').textContent = txt;
  }

  // ---- ready: the first frame is drawn (a one-pixel read waits for the GPU), then the
  // frame time is measured in a task of its own: render + a pixel read, median of three.
  function finishReady() {
    var gl = renderer.getContext(), px = new Uint8Array(4);
    gl.readPixels(0, 0, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, px);
    phases.drawn = performance.now();
    var s = document.getElementById('uavip-state');
    s.setAttribute('data-ready-ms', fmt(phases.drawn, 0));
    s.setAttribute('data-phase-ms', Object.keys(phases).map(function (k) { return k + ':' + fmt(phases[k], 0); }).join(' '));
    document.getElementById('status').textContent = 'ready in ' + fmt(phases.drawn / 1000, 2) + ' s';
    document.title = 'ready';
    setTimeout(function () {
      var times = [];
      for (var k = 0; k < 3; k++) {
        var t0 = performance.now();
        draw();
        gl.readPixels(0, 0, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, px);
        times.push(performance.now() - t0);
      }
      times.sort(function (a, b) { return a - b; });
      s.setAttribute('data-frame-ms', fmt(times[1], 1));
      document.getElementById('status').textContent = 'frame ' + fmt(times[1], 1) + ' ms \u00b7 ready in ' +
        fmt(phases.drawn / 1000, 2) + ' s';
    }, 0);
  }

  try { main(); } catch (e) { fail(e); }
})();
