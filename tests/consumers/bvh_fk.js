// Forward kinematics of a BVH file by a reader not written here: three.js's BVHLoader (Debian's
// libjs-three) and its animation system. Prints CSV: frame, then x,y,z of every named joint (BVH
// units, the file's frame) in the order of the hierarchy; end sites are named <parent>.end.
// usage: node bvh_fk.js FILE.bvh [THREE_DIR=/usr/share/javascript/three]
'use strict';
const fs = require('fs');
const vm = require('vm');
const dir = process.argv[3] || '/usr/share/javascript/three';
globalThis.THREE = require(dir + '/three.min.js');
// The loader's UMD wrapper takes its global branch when neither `exports` nor `define` exist.
vm.runInThisContext(fs.readFileSync(dir + '/examples/js/loaders/BVHLoader.js', 'utf8'));
const result = new THREE.BVHLoader().parse(fs.readFileSync(process.argv[2], 'utf8'));
const bones = result.skeleton.bones;
const root = new THREE.Object3D();
root.add(bones[0]);
root.skeleton = result.skeleton;  // '.bones[name]' track bindings resolve through root.skeleton
const mixer = new THREE.AnimationMixer(root);
const action = mixer.clipAction(result.clip);
action.setLoop(THREE.LoopOnce);  // a repeating clip wraps its last frame's time back to 0
action.clampWhenFinished = true;
action.play();
const names = bones.map((b) => (b.name === 'ENDSITE' ? b.parent.name + '.end' : b.name));
const times = result.clip.tracks[0].times;
const out = ['frame,' + names.map((n) => `${n}_x,${n}_y,${n}_z`).join(',')];
const v = new THREE.Vector3();
for (let f = 0; f < times.length; ++f) {
  mixer.setTime(times[f]);
  root.updateMatrixWorld(true);
  const row = [f];
  for (const b of bones) {
    b.getWorldPosition(v);
    row.push(v.x.toFixed(5), v.y.toFixed(5), v.z.toFixed(5));
  }
  out.push(row.join(','));
}
process.stdout.write(out.join('\n') + '\n');
