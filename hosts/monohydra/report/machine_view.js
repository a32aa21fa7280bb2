// The report's 3D view (machine_view.cpp writes window.MH_VIEW; three.js and
// OrbitControls are inlined before this script). Every body is a group posed
// per frame from the run's coordinates (positions and quaternions computed
// by the report from the CSV rows); parts (actuators, links, lines) are
// placed between their two points' world positions. The first run is drawn
// solid, the others as ghosts. Once the first frame is drawn the canvas gets
// data-monohydra-view="ready" and, after every frame, the attributes a test
// needs: data-monohydra-camera (projection x view, column-major),
// data-monohydra-rect (the canvas on the page), data-monohydra-time and
// data-monohydra-marker.
(function () {
  "use strict";
  var canvas = document.getElementById("mh-view-canvas");
  function fail(err) {
    canvas.setAttribute("data-monohydra-view", "error");
    canvas.setAttribute("data-monohydra-error", String(err && err.message ? err.message : err));
    console.error("monohydra view: " + (err && err.stack ? err.stack : err));
  }
  try {
    start();
  } catch (err) {
    fail(err);
  }

  function start() {
    var D = window.MH_VIEW;
    var T = window.THREE;
    if (!D || !T) throw new Error("the view's data or three.js is missing");
    var nb = D.bodies.length, np = D.parts.length;
    var up = new T.Vector3(D.up[0], D.up[1], D.up[2]);

    // The scene's extent over every frame of every run: sizes of glyphs
    // and the camera follow it.
    var box = new T.Box3();
    D.ground.forEach(function (g) { box.expandByPoint(new T.Vector3(g[0], g[1], g[2])); });
    D.runs.forEach(function (run) {
      var frames = run.t.length;
      for (var f = 0; f < frames; ++f) {
        for (var j = 0; j < nb; ++j) {
          var o = 7 * (f * nb + j);
          box.expandByPoint(new T.Vector3(run.pose[o], run.pose[o + 1], run.pose[o + 2]));
        }
        for (var k = 0; k < 2 * np; ++k) {
          var q = 3 * (f * 2 * np + k);
          box.expandByPoint(new T.Vector3(run.points[q], run.points[q + 1], run.points[q + 2]));
        }
      }
    });
    // and the far ends of shapes and bones, posed
    var rq = new T.Quaternion(), rp = new T.Vector3();
    var ends = D.bodies.map(function (b) {
      var list = b.bones.map(function (p) { return new T.Vector3(p[0], p[1], p[2]); });
      if (b.shape === "beam" || b.shape === "cylinder") list.push(new T.Vector3(b.size[0], 0, 0));
      if (b.shape === "box" || b.shape === "cuboid")
        for (var c = 0; c < 8; ++c)
          list.push(new T.Vector3((c & 1 ? 0.5 : -0.5) * b.size[0], (c & 2 ? 0.5 : -0.5) * b.size[1],
                                  (c & 4 ? 0.5 : -0.5) * b.size[2]).add(new T.Vector3(b.at[0], b.at[1], b.at[2])));
      return list;
    });
    D.runs.forEach(function (run) {
      for (var f = 0; f < run.t.length; ++f)
        for (var j = 0; j < nb; ++j) {
          var o = 7 * (f * nb + j);
          rq.set(run.pose[o + 3], run.pose[o + 4], run.pose[o + 5], run.pose[o + 6]);
          for (var k = 0; k < ends[j].length; ++k) {
            rp.copy(ends[j][k]).applyQuaternion(rq);
            rp.x += run.pose[o]; rp.y += run.pose[o + 1]; rp.z += run.pose[o + 2];
            box.expandByPoint(rp);
          }
        }
    });
    var sphere = box.getBoundingSphere(new T.Sphere());
    var R = Math.max(sphere.radius, 1e-3);
    var thin = 0.006 * R;

    var scene = new T.Scene();
    scene.background = new T.Color(0xf4f5f7);
    scene.add(new T.HemisphereLight(0xffffff, 0x8a8a8a, 0.75));
    var sun = new T.DirectionalLight(0xffffff, 0.6);
    sun.position.set(D.eye[0] + up.x, D.eye[1] + up.y, D.eye[2] + up.z).multiplyScalar(10 * R);
    scene.add(sun);

    // The ground: a grid in the plane through the lowest point, normal to up.
    var grid = new T.GridHelper(2.2 * R, 22, 0xc4c4c4, 0xe0e0e0);
    grid.quaternion.setFromUnitVectors(new T.Vector3(0, 1, 0), up);
    var low = Infinity;
    [box.min, box.max].forEach(function (a) {
      [box.min, box.max].forEach(function (b2) {
        [box.min, box.max].forEach(function (c) {
          low = Math.min(low, new T.Vector3(a.x, b2.y, c.z).dot(up));
        });
      });
    });
    grid.position.copy(sphere.center).addScaledVector(up, low - sphere.center.dot(up));
    scene.add(grid);

    var unitCylinder = new T.CylinderGeometry(1, 1, 1, 20);  // along y, centred
    var unitSphere = new T.SphereGeometry(1, 20, 14);
    var Y = new T.Vector3(0, 1, 0);
    // A cylinder of radius r from a to b (world or body frame).
    function rodBetween(mesh, a, b, r) {
      var d = new T.Vector3().subVectors(b, a);
      var len = d.length();
      mesh.visible = len > 1e-12;
      if (!mesh.visible) return;
      mesh.position.copy(a).addScaledVector(d, 0.5);
      mesh.quaternion.setFromUnitVectors(Y, d.divideScalar(len));
      mesh.scale.set(r, len, r);
    }

    var bodyColours = [0x5b7fb3, 0x6f9a5c, 0xb38a4a, 0x8b6fb0, 0x4f9c9c, 0xa0655a];
    var ghostColours = [0xf28e2b, 0x59a14f, 0xe15759, 0x76b7b2, 0xedc948, 0xb07aa1];
    var scale = D.scale;
    function pressureColour(v, colour) {
      // blue (min) through cyan, green, yellow to red (max): no magenta
      if (v === null || !scale) return colour.set(0x9aa3ad);
      var x = Math.min(1, Math.max(0, (v - scale.min) / (scale.max - scale.min)));
      return colour.setHSL((1 - x) * 0.66, 0.85, 0.5);
    }

    function makeRun(run, r) {
      var ghost = r > 0;
      var group = new T.Group();
      function material(colour) {
        if (!ghost) return new T.MeshStandardMaterial({ color: colour, roughness: 0.6, metalness: 0.1 });
        return new T.MeshBasicMaterial({ color: ghostColours[(r - 1) % ghostColours.length],
                                         transparent: true, opacity: 0.28, depthWrite: false });
      }
      var bodies = D.bodies.map(function (b, j) {
        var g = new T.Group();
        var m = material(bodyColours[j % bodyColours.length]);
        var s = b.size;
        var mesh;
        if (b.shape === "beam") {
          mesh = new T.Mesh(unitCylinder, m);
          rodBetween(mesh, new T.Vector3(), new T.Vector3(s[0], 0, 0), 2.6 * thin);
          g.add(mesh);
        } else if (b.shape === "cylinder") {
          mesh = new T.Mesh(unitCylinder, m);
          rodBetween(mesh, new T.Vector3(), new T.Vector3(s[0], 0, 0), s[1]);
          g.add(mesh);
        } else if (b.shape === "cuboid" || b.shape === "box") {
          mesh = new T.Mesh(new T.BoxGeometry(s[0], s[1], s[2]), m);
          mesh.position.set(b.at[0], b.at[1], b.at[2]);
          g.add(mesh);
        } else {
          // No shape: bones from the joint to every point the body carries,
          // and a ball at its centre of mass.
          b.bones.forEach(function (p) {
            var bone = new T.Mesh(unitCylinder, m);
            rodBetween(bone, new T.Vector3(), new T.Vector3(p[0], p[1], p[2]), 1.3 * thin);
            g.add(bone);
          });
          var com = new T.Mesh(unitSphere, m);
          com.position.set(b.com[0], b.com[1], b.com[2]);
          com.scale.setScalar(2.5 * thin);
          g.add(com);
        }
        if (!ghost) {
          // the joint: a short axle (revolute) or a block (prismatic)
          var jm = new T.MeshStandardMaterial({ color: 0x30343a, roughness: 0.5 });
          var axle = new T.Mesh(b.joint === "revolute" ? unitCylinder : new T.BoxGeometry(1, 1, 1), jm);
          var ax = new T.Vector3(b.axis[0], b.axis[1], b.axis[2]);
          if (b.joint === "revolute") {
            rodBetween(axle, ax.clone().multiplyScalar(-3 * thin), ax.clone().multiplyScalar(3 * thin), 2.2 * thin);
          } else {
            axle.scale.setScalar(4 * thin);
          }
          g.add(axle);
        }
        group.add(g);
        return g;
      });
      var parts = D.parts.map(function (p) {
        var out = { p: p, meshes: [] };
        var grey = ghost ? material(0) : new T.MeshStandardMaterial({ color: 0xb9bec4, metalness: 0.5, roughness: 0.35 });
        if (p.kind === "actuator") {
          // cap chamber, rod chamber, rod
          var cap = ghost ? grey : new T.MeshStandardMaterial({ color: 0x9aa3ad, roughness: 0.5 });
          var rodSide = ghost ? grey : new T.MeshStandardMaterial({ color: 0x9aa3ad, roughness: 0.5 });
          out.meshes = [new T.Mesh(unitCylinder, cap), new T.Mesh(unitCylinder, rodSide),
                        new T.Mesh(unitCylinder, grey)];
        } else if (p.kind === "dot") {
          out.meshes = [new T.Mesh(unitSphere, ghost ? grey : new T.MeshStandardMaterial({ color: 0xc0600b }))];
        } else {
          var link = ghost ? grey : new T.MeshStandardMaterial({ color: p.kind === "link" ? 0x7d858f : 0xc0600b });
          out.meshes = [new T.Mesh(unitCylinder, link)];
        }
        out.meshes.forEach(function (mesh) { group.add(mesh); });
        return out;
      });
      if (!ghost)
        D.cuts.forEach(function (c) {
          var ring = new T.Mesh(new T.TorusGeometry(3 * thin, 0.8 * thin, 8, 24),
                                new T.MeshStandardMaterial({ color: 0x30343a }));
          ring.position.set(c.p[0], c.p[1], c.p[2]);
          if (c.body >= 0) bodies[c.body].add(ring); else group.add(ring);
        });
      var marker = null;
      if (!ghost && D.marker.body >= 0) {
        // transparent (at full opacity) so that it is drawn after the ghosts,
        // which would tint it otherwise, and last of all (renderOrder)
        marker = new T.Mesh(unitSphere, new T.MeshBasicMaterial({ color: 0xff00ff, depthTest: false,
                                                                 transparent: true, opacity: 1 }));
        marker.renderOrder = 10;
        marker.scale.setScalar(Math.max(2.2 * thin, 1e-4));
        marker.position.set(D.marker.p[0], D.marker.p[1], D.marker.p[2]);
        bodies[D.marker.body].add(marker);
      }
      scene.add(group);
      return { run: run, group: group, bodies: bodies, parts: parts, ghost: ghost, marker: marker };
    }

    var views = D.runs.map(makeRun);

    // The frame of `run` at time t: the last frame at or before t.
    function frameAt(run, t) {
      var lo = 0, hi = run.t.length - 1;
      if (t >= run.t[hi]) return hi;
      while (hi - lo > 1) {
        var mid = (lo + hi) >> 1;
        if (run.t[mid] <= t) lo = mid; else hi = mid;
      }
      return lo;
    }
    var a = new T.Vector3(), b = new T.Vector3(), e = new T.Vector3(), piston = new T.Vector3();
    var barrelEnd = new T.Vector3();
    function pose(view, t) {
      var run = view.run, f = frameAt(run, t);
      for (var j = 0; j < nb; ++j) {
        var o = 7 * (f * nb + j), g = view.bodies[j];
        g.position.set(run.pose[o], run.pose[o + 1], run.pose[o + 2]);
        g.quaternion.set(run.pose[o + 3], run.pose[o + 4], run.pose[o + 5], run.pose[o + 6]);
      }
      for (var k = 0; k < np; ++k) {
        var q = 6 * (f * np + k), part = view.parts[k], p = part.p, m = part.meshes;
        a.set(run.points[q], run.points[q + 1], run.points[q + 2]);
        b.set(run.points[q + 3], run.points[q + 4], run.points[q + 5]);
        var va = run.values[2 * (f * np + k)], vb = run.values[2 * (f * np + k) + 1];
        if (p.kind === "actuator") {
          // barrel of length l from a; the rod of length l from b back to the
          // piston (cylinder.cpp's l2 = s - l, l3 = 2 l - s)
          var s = e.subVectors(b, a).length();
          e.divideScalar(Math.max(s, 1e-12));
          var l = p.barrel_length;
          piston.copy(b).addScaledVector(e, -Math.min(l, s));
          barrelEnd.copy(a).addScaledVector(e, l);
          rodBetween(m[0], a, piston, 0.5 * p.barrel_diameter);
          rodBetween(m[1], piston, barrelEnd, 0.5 * p.barrel_diameter);
          rodBetween(m[2], piston, b, 0.5 * p.rod_diameter);
          if (!view.ghost) {
            pressureColour(va, m[0].material.color);
            pressureColour(vb, m[1].material.color);
          }
        } else if (p.kind === "dot") {
          m[0].position.copy(a);
          m[0].scale.setScalar(2 * thin);
        } else {
          rodBetween(m[0], a, b, p.kind === "link" ? 0.5 * p.rod_diameter : thin);
          if (!view.ghost && p.kind === "link" && p.columns[0] !== "") pressureColour(va, m[0].material.color);
        }
      }
    }

    // The ground's fixed points (cut joints ride on their body a, in makeRun).
    var groundMaterial = new T.MeshStandardMaterial({ color: 0x777777 });
    D.ground.forEach(function (g) {
      var mesh = new T.Mesh(new T.ConeGeometry(3 * thin, 6 * thin, 16), groundMaterial);
      mesh.quaternion.setFromUnitVectors(Y, up);
      mesh.position.set(g[0], g[1], g[2]).addScaledVector(up, -3 * thin);
      scene.add(mesh);
    });
    var renderer = new T.WebGLRenderer({ canvas: canvas, antialias: true, preserveDrawingBuffer: true });
    renderer.setPixelRatio(window.devicePixelRatio || 1);
    var width = canvas.clientWidth || canvas.width, height = canvas.clientHeight || canvas.height;
    renderer.setSize(width, height, false);
    var camera = new T.PerspectiveCamera(35, width / height, R / 100, R * 100);
    camera.up.copy(up);
    // Back off along the eye direction until the scene's box fits both ways.
    var eye = new T.Vector3(D.eye[0], D.eye[1], D.eye[2]).normalize();
    var right = new T.Vector3().crossVectors(up, eye).normalize();
    var upOnScreen = new T.Vector3().crossVectors(eye, right);
    var halfW = 0, halfH = 0, halfD = 0, corner = new T.Vector3();
    for (var c = 0; c < 8; ++c) {
      corner.set(c & 1 ? box.max.x : box.min.x, c & 2 ? box.max.y : box.min.y,
                 c & 4 ? box.max.z : box.min.z).sub(sphere.center);
      halfW = Math.max(halfW, Math.abs(corner.dot(right)));
      halfH = Math.max(halfH, Math.abs(corner.dot(upOnScreen)));
      halfD = Math.max(halfD, Math.abs(corner.dot(eye)));
    }
    var tanHalf = Math.tan((35 / 2) * Math.PI / 180);
    var distance = halfD + 1.02 * Math.max(halfH / tanHalf, halfW / (tanHalf * camera.aspect), 0.05 * R);
    camera.position.copy(sphere.center).addScaledVector(eye, distance);
    camera.lookAt(sphere.center);
    var controls = new T.OrbitControls(camera, canvas);
    controls.target.copy(sphere.center);
    controls.update();

    // Time, play, speed, the solid run.
    var solid = 0;
    var run0 = D.runs[0];
    var t0 = run0.t[0], t1 = run0.t[run0.t.length - 1];
    var t = t0, playing = true, speed = 1, dirty = true, last = null;
    var slider = document.getElementById("mh-time");
    var text = document.getElementById("mh-time-text");
    var play = document.getElementById("mh-play");
    var speedSelect = document.getElementById("mh-speed");
    var solidSelect = document.getElementById("mh-solid");
    D.runs.forEach(function (run, r) {
      var opt = document.createElement("option");
      opt.value = String(r);
      opt.textContent = run.label;
      solidSelect.appendChild(opt);
    });
    var hash = /(?:^#|&)t=([^&]+)/.exec(window.location.hash || "");
    if (hash) {
      playing = false;
      t = hash[1] === "end" ? t1 : Math.min(t1, Math.max(t0, parseFloat(hash[1]) || t0));
    }
    function setPlaying(on) {
      playing = on;
      play.textContent = on ? "Pause" : "Play";
      last = null;
    }
    setPlaying(playing);
    play.addEventListener("click", function () { setPlaying(!playing); });
    slider.addEventListener("input", function () {
      setPlaying(false);
      t = t0 + (t1 - t0) * Number(slider.value) / 1000;
      dirty = true;
    });
    speedSelect.addEventListener("change", function () { speed = Number(speedSelect.value); });
    solidSelect.addEventListener("change", function () {
      // the chosen run solid, the others ghosts: rebuild the runs in that order
      solid = Number(solidSelect.value);
      views.forEach(function (v) { scene.remove(v.group); });
      var order = [solid].concat(D.runs.map(function (_, r) { return r; }).filter(function (r) { return r !== solid; }));
      views = order.map(function (r, i) { return makeRun(D.runs[r], i); });
      dirty = true;
    });
    controls.addEventListener("change", function () { dirty = true; });

    // The legend: the colour scale of the chambers.
    var legend = document.getElementById("mh-legend");
    if (scale) {
      var mega = scale.unit === "Pa";
      var fmt = function (v) { return mega ? (v / 1e6).toFixed(2) + " MPa" : v.toPrecision(4) + " " + scale.unit; };
      var stops = [];
      for (var i = 0; i <= 10; ++i) stops.push("hsl(" + Math.round((1 - i / 10) * 237.6) + ",85%,50%)");
      legend.innerHTML = "";
      var lo = document.createElement("span"); lo.textContent = fmt(scale.min);
      var bar = document.createElement("span"); bar.className = "mh-bar";
      bar.style.background = "linear-gradient(to right," + stops.join(",") + ")";
      var hi = document.createElement("span"); hi.textContent = fmt(scale.max);
      var what = document.createElement("span"); what.textContent = " chamber pressure (cap side from the barrel's end, rod side toward the rod)";
      [lo, bar, hi, what].forEach(function (x) { legend.appendChild(x); });
    } else {
      legend.textContent = "No component declared a pressure to colour by.";
    }

    var projection = new T.Matrix4();
    function publish() {
      projection.multiplyMatrices(camera.projectionMatrix, camera.matrixWorldInverse);
      // the drawing's box: inside the canvas's border
      var rect = canvas.getBoundingClientRect();
      canvas.setAttribute("data-monohydra-camera", JSON.stringify(projection.elements));
      canvas.setAttribute("data-monohydra-rect", JSON.stringify([
        rect.left + window.scrollX + canvas.clientLeft, rect.top + window.scrollY + canvas.clientTop,
        canvas.clientWidth, canvas.clientHeight]));
      canvas.setAttribute("data-monohydra-time", String(views[0].run.t[frameAt(views[0].run, t)]));
      canvas.setAttribute("data-monohydra-marker", JSON.stringify(D.marker));
    }
    function draw() {
      views.forEach(function (v) { pose(v, t); });
      renderer.render(scene, camera);
      slider.value = String(Math.round(1000 * (t - t0) / Math.max(t1 - t0, 1e-12)));
      text.textContent = "t = " + t.toFixed(3) + " s";
      publish();
      dirty = false;
    }
    function tick(now) {
      if (playing) {
        if (last !== null) {
          t += speed * (now - last) / 1000;
          if (t > t1) t = t0 + (t - t1) % Math.max(t1 - t0, 1e-9);
          dirty = true;
        }
        last = now;
      }
      if (dirty) draw();
      window.requestAnimationFrame(tick);
    }
    draw();
    canvas.setAttribute("data-monohydra-view", "ready");
    window.monohydraView = {
      setTime: function (s) { setPlaying(false); t = Math.min(t1, Math.max(t0, s)); draw(); },
      play: function () { setPlaying(true); },
      pause: function () { setPlaying(false); },
      camera: camera,
      scene: scene
    };
    window.requestAnimationFrame(tick);
  }
})();
