// Writes threejs_sphere.obj with three.js's own OBJExporter (three from web/node_modules):
//   node tests/data/obj/make_threejs.mjs
// A sphere (radius 1, Y up) in a group with a Unicode name, as a three.js scene exports it:
// o lines, v/vt/vn of one count, every face as v/vt/vn triangles, no materials.
import fs from 'node:fs';
import path from 'node:path';
import {fileURLToPath} from 'node:url';

const here = path.dirname(fileURLToPath(import.meta.url));
const three = path.join(here, '../../../web/node_modules/three');
const THREE = await import(path.join(three, 'build/three.module.js'));
const {OBJExporter} = await import(path.join(three, 'examples/jsm/exporters/OBJExporter.js'));

const mesh = new THREE.Mesh(new THREE.SphereGeometry(1, 16, 8), new THREE.MeshBasicMaterial());
mesh.name = 'Tête_頭';
const scene = new THREE.Scene();
scene.add(mesh);
fs.writeFileSync(path.join(here, 'threejs_sphere.obj'), new OBJExporter().parse(scene));
