// The fit report's interactive views and timings table. Runs from disk
// (file://): the models come embedded as base64 strings in scripts
// (window.GP_MODELS) because browsers refuse to fetch files from file:// pages.
(function () {
  'use strict';

  function decodeBase64(text) {
    const bytes = atob(text);
    const out = new Uint8Array(bytes.length);
    for (let i = 0; i < bytes.length; ++i) out[i] = bytes.charCodeAt(i);
    return out.buffer;
  }

  function setUpViewer(element) {
    const id = element.dataset.model;
    const data = (window.GP_MODELS || {})[id];
    if (!data) {
      console.error('fit report: the model ' + id + ' is missing');
      return;
    }
    const canvas = element.querySelector('canvas');
    const renderer = new THREE.WebGLRenderer({canvas: canvas, antialias: true, preserveDrawingBuffer: true});
    renderer.outputEncoding = THREE.sRGBEncoding;
    renderer.setClearColor(0xffffff, 1);
    const scene = new THREE.Scene();
    const camera = new THREE.PerspectiveCamera(30, canvas.width / canvas.height, 0.01, 100);
    scene.add(new THREE.HemisphereLight(0xffffff, 0x606060, 0.55));
    const light = new THREE.DirectionalLight(0xffffff, 0.75);
    light.position.set(-0.6, 0.8, 1.5);
    camera.add(light);
    scene.add(camera);
    const controls = new THREE.OrbitControls(camera, canvas);
    const draw = function () { renderer.render(scene, camera); };
    controls.addEventListener('change', draw);

    new THREE.GLTFLoader().parse(decodeBase64(data), '', function (gltf) {
      scene.add(gltf.scene);
      const garment = gltf.scene.getObjectByName('garment');
      const body = gltf.scene.getObjectByName('body');
      const box = new THREE.Box3().setFromObject(garment || gltf.scene);
      const centre = box.getCenter(new THREE.Vector3());
      const size = box.getSize(new THREE.Vector3()).length();
      const front = (element.dataset.front || '0,0,1').split(',').map(Number);
      controls.target.copy(centre);
      camera.position.set(centre.x + 1.9 * size * front[0], centre.y + 1.9 * size * front[1],
                          centre.z + 1.9 * size * front[2]);
      camera.near = size / 200;
      camera.far = size * 50;
      camera.updateProjectionMatrix();
      controls.update();
      const checkbox = element.querySelector('.show-body');
      if (checkbox && body) {
        checkbox.addEventListener('change', function () {
          body.visible = checkbox.checked;
          draw();
        });
      }
      draw();
      element.dataset.rendered = '1';
    }, function (error) {
      console.error('fit report: cannot load the model ' + id + ': ' + error);
    });
  }

  // The total of a stage's timing.json, wherever that stage keeps it.
  function timingTotal(timing) {
    const candidates = [['total_s'], ['build_total']];
    for (const path of candidates) {
      let v = timing;
      for (const key of path) v = v && typeof v === 'object' ? v[key] : undefined;
      if (typeof v === 'number') return {value: v, pointer: '/' + path.join('/')};
    }
    return null;
  }

  function phases(timing, prefix, out) {
    for (const key of Object.keys(timing)) {
      const v = timing[key];
      if (typeof v === 'number' && !/total/.test(key)) out.push(prefix + key + ' ' + v.toFixed(2));
      else if (v && typeof v === 'object' && !Array.isArray(v)) phases(v, prefix + key + '/', out);
    }
    return out;
  }

  function fillTimings() {
    const table = document.getElementById('timings-table');
    if (!table) return;
    for (const t of window.GP_TIMINGS || []) {
      const row = table.insertRow();
      row.insertCell().textContent = t.stage;
      const total = timingTotal(t.timing);
      const cell = row.insertCell();
      if (total) {
        const span = document.createElement('span');
        span.className = 'timing';
        span.dataset.src = t.file;
        span.dataset.ptr = total.pointer;
        span.textContent = total.value.toFixed(2);
        cell.appendChild(span);
      } else {
        cell.textContent = '\u2013';
      }
      row.insertCell().textContent = phases(t.timing, '', []).join(', ');
    }
  }

  fillTimings();
  document.querySelectorAll('.viewer').forEach(setUpViewer);
})();
