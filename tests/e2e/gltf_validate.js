// Runs the Khronos glTF-Validator on .glb files: node gltf_validate.js MODULES_DIR FILE...
// Prints one line per file (errors, warnings, infos, hints and the error messages) and exits 1
// when any file has an error or a warning.
const path = require('path');
const fs = require('fs');
const validator = require(path.resolve(process.argv[2], 'node_modules', 'gltf-validator'));

async function main() {
  let failed = false;
  for (const file of process.argv.slice(3)) {
    const report = await validator.validateBytes(new Uint8Array(fs.readFileSync(file)), {
      uri: path.basename(file),
      maxIssues: 0,
      externalResourceFunction: (uri) => Promise.reject(new Error('external resource ' + uri)),
    });
    const issues = report.issues;
    console.log(`${file}: ${issues.numErrors} errors, ${issues.numWarnings} warnings, ${issues.numInfos} infos, ` +
                `${issues.numHints} hints (glTF-Validator ${report.validatorVersion})`);
    const counts = {};
    for (const m of issues.messages) {
      const key = `${['error', 'warning', 'info', 'hint'][m.severity]} ${m.code}`;
      if (m.severity <= 1 && (counts[key] || 0) < 3) console.log(`  ${key} ${m.pointer || ''}: ${m.message}`);
      counts[key] = (counts[key] || 0) + 1;
    }
    for (const [key, n] of Object.entries(counts)) console.log(`  ${n} × ${key}`);
    if (issues.numErrors > 0 || issues.numWarnings > 0) failed = true;
  }
  process.exit(failed ? 1 : 0);
}
main().catch((e) => { console.error(e); process.exit(2); });
