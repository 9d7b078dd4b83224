// Runs the Khronos glTF Validator (npm package gltf-validator) on one .gltf or .glb file.
// Usage: node validate.cjs FILE
// Prints one JSON line: {"errors": N, "warnings": N, "messages": [first error messages]}.
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

const file = process.argv[2];
const validator = loadValidator();
const bytes = fs.readFileSync(file);
validator
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
      errors: report.issues.numErrors,
      warnings: report.issues.numWarnings,
      messages,
      warning_messages: warnings,
    }));
  })
  .catch((error) => {
    console.error("validator failed: " + error);
    process.exit(2);
  });
