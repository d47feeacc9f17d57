#!/usr/bin/env node
// Runs the Khronos glTF validator (npm package gltf-validator, installed by tools/setup.sh into tools/node) on
// each .gltf/.glb named on the command line, external .bin files included.
// Prints one line per file, "FILE: numErrors N numWarnings M", then each error as "  CODE POINTER: message".
// Exit status: 0 when no file has an error, 1 when one does, 2 when the validator cannot run or read a file.
'use strict';
const fs = require('fs');
const path = require('path');

let validator;
try {
  validator = require(path.join(__dirname, 'node', 'node_modules', 'gltf-validator'));
} catch (e) {
  console.error('validate-gltf: gltf-validator is not installed (run tools/setup.sh): ' + e.message);
  process.exit(2);
}

async function validate(file) {
  const bytes = new Uint8Array(fs.readFileSync(file));
  const report = await validator.validateBytes(bytes, {
    uri: path.basename(file),
    maxIssues: 0,
    writeTimestamp: false,
    externalResourceFunction: (uri) => new Promise((resolve, reject) => {
      fs.readFile(path.resolve(path.dirname(file), decodeURIComponent(uri)),
                  (err, data) => (err ? reject(err.toString()) : resolve(new Uint8Array(data))));
    }),
  });
  const issues = report.issues;
  console.log(`${file}: numErrors ${issues.numErrors} numWarnings ${issues.numWarnings}`);
  for (const m of issues.messages)
    if (m.severity === 0)
      console.log(`  ${m.code} ${m.pointer || ''}: ${m.message}`);
  return issues.numErrors;
}

(async () => {
  const files = process.argv.slice(2);
  if (files.length === 0) {
    console.error('usage: validate-gltf.js FILE.gltf|FILE.glb ...');
    process.exit(2);
  }
  let errors = 0;
  for (const f of files) {
    try {
      errors += await validate(f);
    } catch (e) {
      console.error(`validate-gltf: ${f}: ${e}`);
      process.exit(2);
    }
  }
  process.exit(errors ? 1 : 0);
})();
