// uavip mission page, edit mode: the operator corrects what the scan got
// wrong before the flight. Pick a surface, drag its boundary vertices in its plane,
// insert and remove vertices, delete it or merge others into it, draw keep-out boxes
// and move or resize them; "Save edits" downloads edits.yaml (app/edits.h, the format
// of docs/formats.md) and shows the `uavip plan ... --edits edits.yaml` command.
// Uses only what mission_page.js exposes as window.uavipPage.
//
// Test hook (the browser test): the URL hash `edit=S:V:DX:DY` turns the edit mode on,
// picks surface S and drags its vertex V by (DX, DY) CSS pixels with real pointer
// events on the canvas, then saves; the YAML is in #edit-yaml, the state in
// #uavip-state's data-edit-* attributes.
(function () {
  'use strict';
  var P = window.uavipPage;
  var panel = document.getElementById('edit');
  if (!P || !panel) return;
  var D = P.data, O = P.origin;

  // ---- state: per surface its edited boundary (world metres), deletion, merges
  var edits = {};  // id -> {boundary: [[x,y,z]...], changed, deleted, merge: []}
  var boxes = [];  // {name, center: [x,y,z], size: [x,y,z], yaw}
  var on = false, sel = null, vsel = -1, bsel = -1, drag = null;
  var handles = null, loop = null, boxObjs = [];

  function surf(id) { return D.surfaces.filter(function (s) { return s.id === id; })[0]; }
  function edited(id) {
    if (!edits[id]) {
      var s = surf(id);
      edits[id] = { boundary: s.edit.boundary_m.map(function (p) { return p.slice(); }), changed: false, deleted: false, merge: [] };
    }
    return edits[id];
  }
  function local(p) { return new THREE.Vector3(p[0] - O[0], p[1] - O[1], p[2] - O[2]); }

  // ---- the panel
  function el(tag, attrs, text) {
    var e = document.createElement(tag);
    Object.keys(attrs || {}).forEach(function (k) { e.setAttribute(k, attrs[k]); });
    if (text) e.textContent = text;
    return e;
  }
  function button(id, text, fn, parent) {
    var b = el('button', { id: id }, text);
    b.addEventListener('click', function () { fn(); redraw(); });
    (parent || panel).appendChild(b);
    return b;
  }
  var toggle = el('input', { type: 'checkbox', id: 'edit-on' });
  var lab = el('label');
  lab.appendChild(toggle);
  lab.appendChild(document.createTextNode('edit mode'));
  panel.appendChild(lab);
  var pickSel = el('select', { id: 'edit-surface' });
  pickSel.appendChild(el('option', { value: '' }, 'surface\u2026'));
  D.surfaces.forEach(function (s) { pickSel.appendChild(el('option', { value: String(s.id) }, 'surface ' + s.id + ' (' + s.area_m2 + ' m\u00b2)')); });
  panel.appendChild(pickSel);
  var tools = el('div');
  panel.appendChild(tools);
  button('edit-insert', '+ vertex', insertVertex, tools);
  button('edit-remove', '\u2212 vertex', removeVertex, tools);
  button('edit-delete', 'delete surface', deleteSurface, tools);
  var mergeIn = el('input', { id: 'edit-merge', size: '6', placeholder: 'ids' });
  tools.appendChild(mergeIn);
  button('edit-merge-btn', 'merge', mergeSurfaces, tools);
  button('edit-box', 'add keep-out box', addBox, tools);
  var boxForm = el('div', { id: 'edit-box-form' });
  panel.appendChild(boxForm);
  var fields = {};
  ['cx', 'cy', 'cz', 'sx', 'sy', 'sz', 'yaw'].forEach(function (k) {
    var f = el('input', { id: 'edit-box-' + k, size: '4', title: k });
    f.addEventListener('change', function () { fromFields(); redraw(); });
    fields[k] = f;
    boxForm.appendChild(document.createTextNode(' ' + k + ' '));
    boxForm.appendChild(f);
  });
  button('edit-save', 'Save edits', save);
  var status = el('div', { id: 'edit-status' }, 'Turn on the edit mode, then pick a surface.');
  panel.appendChild(status);
  var yamlOut = el('pre', { id: 'edit-yaml', style: 'font-size:10px;max-height:8em;overflow:auto' });
  var cmdOut = el('div', { id: 'edit-cmd', style: 'font:11px monospace' });
  panel.appendChild(yamlOut);
  panel.appendChild(cmdOut);
  toggle.addEventListener('change', function () { on = toggle.checked; redraw(); });
  pickSel.addEventListener('change', function () { select(pickSel.value === '' ? null : +pickSel.value); redraw(); });

  function select(id) {
    sel = id;
    vsel = -1;
    pickSel.value = id === null ? '' : String(id);
  }
  function insertVertex() {
    if (sel === null) return;
    var b = edited(sel).boundary, i = vsel < 0 ? 0 : vsel, j = (i + 1) % b.length;
    b.splice(i + 1, 0, [0, 1, 2].map(function (k) { return (b[i][k] + b[j][k]) / 2; }));
    edited(sel).changed = true;
    vsel = i + 1;
  }
  function removeVertex() {
    if (sel === null || vsel < 0) return;
    var b = edited(sel).boundary;
    if (b.length <= 3) { status.textContent = 'A boundary keeps at least 3 vertices.'; return; }
    b.splice(vsel, 1);
    edited(sel).changed = true;
    vsel = Math.min(vsel, b.length - 1);
  }
  function deleteSurface() { if (sel !== null) edited(sel).deleted = !edited(sel).deleted; }
  function mergeSurfaces() {
    if (sel === null) return;
    edited(sel).merge = mergeIn.value.split(/[ ,]+/).filter(function (t) { return t !== ''; }).map(Number)
      .filter(function (m) { return m !== sel && surf(m); });
  }
  function addBox() {
    var s = sel !== null ? surf(sel) : null, c;
    if (s) c = s.centroid.map(function (v, k) { return v + 3 * s.normal[k]; });
    else c = [P.controls.target.x + O[0], P.controls.target.y + O[1], P.controls.target.z + O[2]];
    boxes.push({ name: 'keep-out ' + (boxes.length + 1), center: c, size: [2, 2, 2], yaw: 0 });
    bsel = boxes.length - 1;
    toFields();
  }
  function toFields() {
    var b = boxes[bsel];
    if (!b) return;
    fields.cx.value = b.center[0].toFixed(2); fields.cy.value = b.center[1].toFixed(2); fields.cz.value = b.center[2].toFixed(2);
    fields.sx.value = b.size[0]; fields.sy.value = b.size[1]; fields.sz.value = b.size[2]; fields.yaw.value = b.yaw;
  }
  function fromFields() {
    var b = boxes[bsel];
    if (!b) return;
    var num = function (f, d) { var v = parseFloat(f.value); return isFinite(v) ? v : d; };
    b.center = [num(fields.cx, b.center[0]), num(fields.cy, b.center[1]), num(fields.cz, b.center[2])];
    b.size = [Math.max(0.1, num(fields.sx, b.size[0])), Math.max(0.1, num(fields.sy, b.size[1])), Math.max(0.1, num(fields.sz, b.size[2]))];
    b.yaw = num(fields.yaw, b.yaw);
  }

  // ---- drawing: the chosen surface's boundary and handles, the keep-out boxes
  function redraw() {
    [handles, loop].concat(boxObjs).forEach(function (o) { if (o) P.scene.remove(o); });
    handles = loop = null;
    boxObjs = [];
    if (on && sel !== null) {
      var e = edited(sel), pts = [];
      e.boundary.forEach(function (p) { var v = local(p); pts.push(v.x, v.y, v.z); });
      var g = new THREE.BufferGeometry();
      g.setAttribute('position', new THREE.BufferAttribute(new Float32Array(pts), 3));
      loop = new THREE.LineLoop(g, new THREE.LineBasicMaterial({ color: e.deleted ? 0x888888 : 0xd00000, depthTest: false }));
      loop.renderOrder = 20;
      var col = new Float32Array(pts.length);
      for (var i = 0; i < col.length / 3; i++) col[3 * i + 2] = i === vsel ? 1 : 0;
      var hg = new THREE.BufferGeometry();
      hg.setAttribute('position', new THREE.BufferAttribute(new Float32Array(pts), 3));
      hg.setAttribute('color', new THREE.BufferAttribute(col, 3));
      handles = new THREE.Points(hg, new THREE.PointsMaterial({ size: 9, sizeAttenuation: false, vertexColors: THREE.VertexColors, depthTest: false }));
      handles.renderOrder = 21;
      P.scene.add(loop);
      P.scene.add(handles);
    }
    if (on) {
      boxes.forEach(function (b, k) {
        var m = new THREE.LineSegments(new THREE.EdgesGeometry(new THREE.BoxGeometry(b.size[0], b.size[1], b.size[2])),
          new THREE.LineBasicMaterial({ color: k === bsel ? 0xff6600 : 0x993300, depthTest: false }));
        m.position.copy(local(b.center));
        m.rotation.z = b.yaw * Math.PI / 180;
        m.renderOrder = 22;
        boxObjs.push(m);
        P.scene.add(m);
      });
    }
    var n = Object.keys(edits).filter(function (id) { var e = edits[id]; return e.changed || e.deleted || e.merge.length; }).length;
    status.textContent = !on ? 'Edit mode is off.' : sel === null ? 'Pick a surface (or add a keep-out box).' :
      'surface ' + sel + ': ' + edited(sel).boundary.length + ' vertices' + (vsel >= 0 ? ', vertex ' + vsel + ' selected' : '') +
      (edited(sel).deleted ? ', deleted' : '') + ' \u00b7 ' + n + ' surface(s) and ' + boxes.length + ' keep-out(s) edited';
    publish();
    P.requestDraw();
  }
  function publish() {
    var s = document.getElementById('uavip-state');
    if (!s) return;
    s.setAttribute('data-edit-on', on ? 'true' : 'false');
    s.setAttribute('data-edit-surface', sel === null ? '' : String(sel));
    s.setAttribute('data-edit-boundary', sel === null ? '' : JSON.stringify(edited(sel).boundary));
    s.setAttribute('data-edit-boxes', String(boxes.length));
  }

  // ---- pointer: drag a handle in the surface's plane, a box's centre horizontally
  function screen(p) {
    var r = P.canvas.getBoundingClientRect(), v = local(p).project(P.camera);
    return [r.left + (v.x + 1) / 2 * r.width, r.top + (1 - v.y) / 2 * r.height];
  }
  function rayHit(ev, planeNormal, planePoint) {
    var r = P.canvas.getBoundingClientRect();
    var ndc = new THREE.Vector2((ev.clientX - r.left) / r.width * 2 - 1, -((ev.clientY - r.top) / r.height) * 2 + 1);
    var rc = new THREE.Raycaster();
    rc.setFromCamera(ndc, P.camera);
    var plane = new THREE.Plane().setFromNormalAndCoplanarPoint(planeNormal, local(planePoint));
    var hit = new THREE.Vector3();
    if (!rc.ray.intersectPlane(plane, hit)) return null;
    return [hit.x + O[0], hit.y + O[1], hit.z + O[2]];
  }
  function nearest(list, ev, radius) {
    var best = -1, bd = radius * radius;
    list.forEach(function (p, i) {
      var s = screen(p), d = (s[0] - ev.clientX) * (s[0] - ev.clientX) + (s[1] - ev.clientY) * (s[1] - ev.clientY);
      if (d < bd) { bd = d; best = i; }
    });
    return best;
  }
  P.canvas.addEventListener('pointerdown', function (ev) {
    if (!on) return;
    var bi = nearest(boxes.map(function (b) { return b.center; }), ev, 10);
    if (bi >= 0) {
      bsel = bi; toFields();
      drag = { box: bi };
    } else if (sel !== null) {
      var vi = nearest(edited(sel).boundary, ev, 10);
      if (vi < 0) return;
      vsel = vi;
      drag = { vertex: vi };
    } else {
      return;
    }
    P.controls.enabled = false;  // the drag moves the handle, not the camera
    ev.preventDefault();
    ev.stopPropagation();
    redraw();
  }, true);
  window.addEventListener('pointermove', function (ev) {
    if (!drag) return;
    if (drag.box !== undefined) {
      var b = boxes[drag.box], h = rayHit(ev, new THREE.Vector3(0, 0, 1), b.center);
      if (h) { b.center = [h[0], h[1], b.center[2]]; toFields(); }
    } else {
      var s = surf(sel), n = new THREE.Vector3(s.normal[0], s.normal[1], s.normal[2]);
      var p = rayHit(ev, n, s.centroid);
      if (p) { edited(sel).boundary[drag.vertex] = p; edited(sel).changed = true; }
    }
    redraw();
  });
  window.addEventListener('pointerup', function () {
    if (!drag) return;
    drag = null;
    P.controls.enabled = true;
    redraw();
  });

  // ---- saving: the edits file (docs/formats.md "Edits file")
  function pt(p) { return '[' + p.map(function (v) { return String(Math.round(v * 1e6) / 1e6); }).join(', ') + ']'; }
  function yaml() {
    var out = 'uavip-edits: 1\n', ids = Object.keys(edits).map(Number).sort(function (a, b) { return a - b; });
    var list = ids.filter(function (id) { var e = edits[id]; return e.changed || e.deleted || e.merge.length; });
    if (list.length) out += 'surfaces:\n';
    list.forEach(function (id) {
      var s = surf(id), e = edits[id];
      out += '  - id: ' + id + '\n    fingerprint: {centroid: ' + pt(s.centroid) + ', normal: ' + pt(s.normal) + '}\n';
      if (e.deleted) { out += '    delete: true\n'; return; }
      if (e.changed) out += '    boundary: [' + e.boundary.map(pt).join(', ') + ']\n';
      if (e.merge.length) out += '    merge: [' + e.merge.join(', ') + ']\n';
    });
    if (boxes.length) out += 'keep_out:\n';
    boxes.forEach(function (b) {
      out += '  - name: "' + b.name + '"\n    box: {center: ' + pt(b.center) + ', size: ' + pt(b.size) + ', yaw_deg: ' + b.yaw + '}\n';
    });
    return out;
  }
  function save() {
    var text = yaml();
    yamlOut.textContent = text;
    cmdOut.textContent = 'uavip plan OUT/scene.json --surface all --edits edits.yaml -o OUT-edited';
    try {
      var a = document.createElement('a');
      a.href = URL.createObjectURL(new Blob([text], { type: 'text/yaml' }));
      a.download = 'edits.yaml';
      document.body.appendChild(a);
      if (!/edit=/.test(location.hash)) a.click();  // the test hook reads #edit-yaml instead
      document.body.removeChild(a);
    } catch (e) { /* the text stays in #edit-yaml */ }
  }

  // ---- the test hook: #edit=S:V:DX:DY
  var m = /(?:^#|&)edit=(\d+):(\d+):(-?[\d.]+):(-?[\d.]+)/.exec(location.hash);
  if (m && surf(+m[1])) {
    toggle.checked = on = true;
    select(+m[1]);
    redraw();
    var v = edited(sel).boundary[+m[2]];
    if (v) {
      var s0 = screen(v), opts = function (x, y) { return { clientX: x, clientY: y, bubbles: true, pointerId: 1, isPrimary: true }; };
      P.canvas.dispatchEvent(new PointerEvent('pointerdown', opts(s0[0], s0[1])));
      window.dispatchEvent(new PointerEvent('pointermove', opts(s0[0] + +m[3] / 2, s0[1] + +m[4] / 2)));
      window.dispatchEvent(new PointerEvent('pointermove', opts(s0[0] + +m[3], s0[1] + +m[4])));
      window.dispatchEvent(new PointerEvent('pointerup', opts(s0[0] + +m[3], s0[1] + +m[4])));
    }
    save();
  }
  redraw();
})();
