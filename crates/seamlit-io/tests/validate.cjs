// Runs the Khronos glTF Validator (npm package gltf-validator) on .gltf or .glb files.
// Usage: node validate.cjs FILE [FILE...]
// Prints one JSON line per file, in order: {"file": FILE, "errors": N, "warnings": N,
// "messages": [first error messages], "warning_messages": [...]}. One node start-up for
// many files saves about a quarter of a second per file.
// The validator is looked up in the repository's .ci/node (installed by .ci/run), then in
// the ordinary module path.
"use strict";
const fs = require("fs");
const path = require("path");

function loadValidator() {
  const local = path.join(__dirname, "..", "..", "..", ".ci", "node", "node_modules", "gltf-validator");
  try {
    return require(local);
  } catch (_) {
    return require("gltf-validator");
  }
}

function validate(file) {
  const bytes = fs.readFileSync(file);
  return validator
    .validateBytes(new Uint8Array(bytes), {
      uri: path.basename(file),
      maxIssues: 100,
      externalResourceFunction: (uri) =>
        new Promise((resolve, reject) => {
          fs.readFile(path.resolve(path.dirname(file), decodeURIComponent(uri)), (err, data) =>
            err ? reject(err.toString()) : resolve(new Uint8Array(data)));
        }),
    })
    .then((report) => {
      const messages = report.issues.messages
        .filter((m) => m.severity === 0)
        .slice(0, 10)
        .map((m) => `${m.code} at ${m.pointer || ""}: ${m.message}`);
      const warnings = report.issues.messages
        .filter((m) => m.severity === 1)
        .slice(0, 10)
        .map((m) => `${m.code} at ${m.pointer || ""}: ${m.message}`);
      console.log(JSON.stringify({
        file,
        errors: report.issues.numErrors,
        warnings: report.issues.numWarnings,
        messages,
        warning_messages: warnings,
      }));
    });
}

const validator = loadValidator();
process.argv
  .slice(2)
  .reduce((done, file) => done.then(() => validate(file)), Promise.resolve())
  .catch((error) => {
    console.error("validator failed: " + error);
    process.exit(2);
  });
