#!/usr/bin/env node
// Validates glTF files with the Khronos glTF Validator (npm gltf-validator,
// installed by scripts/setup_node.sh into build/node/).
//
//   node tests/cli/gltf_validate.js FILE.gltf|FILE.glb ...
//
// Prints one summary line per file and every error and warning message;
// exits 1 if any file has an error (warnings are printed, not fatal), 2 when
// the validator cannot be loaded.  GLTF_VALIDATOR names another install of
// the package (a folder or module path).
'use strict';
const fs = require('fs');
const path = require('path');

let validator;
const where = process.env.GLTF_VALIDATOR ||
  path.join(__dirname, '..', '..', 'build', 'node', 'node_modules', 'gltf-validator');
try {
  validator = require(where);
} catch (e) {
  console.error(`gltf_validate: cannot load gltf-validator from ${where}: ${e.message}`);
  console.error('gltf_validate: run  bash scripts/setup_node.sh  (needs node, npm and the npm registry)');
  process.exit(2);
}

const SEVERITY = ['error', 'warning', 'info', 'hint'];

async function validate(file) {
  const bytes = new Uint8Array(fs.readFileSync(file));
  const dir = path.dirname(file);
  const report = await validator.validateBytes(bytes, {
    uri: path.basename(file),
    maxIssues: 100,
    // External buffers (NAME.bin next to NAME.gltf).
    externalResourceFunction: (uri) => new Promise((resolve, reject) => {
      fs.readFile(path.join(dir, decodeURIComponent(uri)), (err, data) => {
        if (err) reject(err.toString()); else resolve(new Uint8Array(data));
      });
    }),
  });
  const is = report.issues;
  console.log(`${file}: ${is.numErrors} errors, ${is.numWarnings} warnings, ` +
              `${is.numInfos} infos, ${is.numHints} hints`);
  for (const m of is.messages) {
    if (m.severity <= 1) {
      console.log(`  ${SEVERITY[m.severity]} ${m.code}: ${m.message}${m.pointer ? ' (' + m.pointer + ')' : ''}`);
    }
  }
  return is.numErrors;
}

async function main() {
  const files = process.argv.slice(2);
  if (files.length === 0) {
    console.error('usage: node tests/cli/gltf_validate.js FILE.gltf|FILE.glb ...');
    process.exit(2);
  }
  let bad = 0;
  for (const f of files) {
    try {
      if (await validate(f) > 0) bad++;
    } catch (e) {
      console.log(`${f}: cannot validate: ${e}`);
      bad++;
    }
  }
  process.exit(bad ? 1 : 0);
}

main();
