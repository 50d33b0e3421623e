// An ADS client we did not write (the npm package ads-client, 2.x) against `hybridtest bench
// --protocol ads`: reads every symbol of the profile by name with its type and size, takes
// handles, enables the drive and drives one command to its acknowledgement.
//
//   node peer.js HOST PORT ACTUATORS
//
// Prints one line "ads-client peer: OK ..." and exits 0, or prints what failed and exits 1.
'use strict';
const { Client } = require('ads-client');

const [host, port, actuatorsText] = process.argv.slice(2);
const n = Number(actuatorsText || '1');
const array = `ARRAY [1..${n}] OF LREAL`;
const profile = {
  'GVL_Hybrid.fCommand': [array, 8 * n], 'GVL_Hybrid.nCommandSeq': ['UDINT', 4],
  'GVL_Hybrid.fPosition': [array, 8 * n], 'GVL_Hybrid.fForce': [array, 8 * n],
  'GVL_Hybrid.nAckSeq': ['UDINT', 4], 'GVL_Hybrid.bEnable': ['BOOL', 1],
  'GVL_Hybrid.bHold': ['BOOL', 1], 'GVL_Hybrid.bEnabled': ['BOOL', 1],
  'GVL_Hybrid.bFault': ['BOOL', 1], 'GVL_Hybrid.bHolding': ['BOOL', 1],
  'GVL_Hybrid.nHeartbeat': ['UDINT', 4],
};

function check(condition, message) {
  if (!condition) throw new Error(message);
}

const reals = (buffer) => Array.from({ length: buffer.length / 8 }, (_, i) => buffer.readDoubleLE(8 * i));
function realsBuffer(values) {
  const b = Buffer.alloc(8 * values.length);
  values.forEach((v, i) => b.writeDoubleLE(v, 8 * i));
  return b;
}
function udint(value) {
  const b = Buffer.alloc(4);
  b.writeUInt32LE(value);
  return b;
}

async function main() {
  const client = new Client({
    targetAmsNetId: '127.0.0.1.1.1', targetAdsPort: 851, routerAddress: host,
    routerTcpPort: Number(port), rawClient: true, autoReconnect: false, timeoutDelay: 5000,
    hideConsoleWarnings: true,
  });
  await client.connect();
  const state = await client.readState();
  check(state.adsState === 5, `ReadState: ADS state ${state.adsState}, expected 5 (RUN)`);
  const info = await client.readDeviceInfo();
  // Every symbol by name: its type and size (0xF009), then a handle (0xF003).
  const handles = {};
  for (const [name, [type, size]] of Object.entries(profile)) {
    const s = await client.getSymbol(name);
    check(s.type === type && s.size === size,
      `${name}: type ${s.type} (${s.size} bytes), expected ${type} (${size} bytes)`);
    const h = await client.createVariableHandle(name);
    check(h.size === size && h.dataType === type, `${name}: handle of ${h.dataType} (${h.size} bytes)`);
    handles[name] = h;
  }
  const read = (name) => client.readRawByHandle(handles[name]);
  const write = (name, buffer) => client.writeRawByHandle(handles[name], buffer);
  // Enable, then one command to its acknowledgement.
  await write('GVL_Hybrid.bHold', Buffer.from([0]));
  await write('GVL_Hybrid.bEnable', Buffer.from([1]));
  check((await read('GVL_Hybrid.bEnabled'))[0] === 1, 'bEnabled is not TRUE after bEnable');
  check((await read('GVL_Hybrid.bHolding'))[0] === 0, 'bHolding is TRUE after bHold := FALSE');
  const start = reals(await read('GVL_Hybrid.fPosition'));
  const command = start.map((p, k) => p + 0.25 * (k + 1));
  const sequence = (await read('GVL_Hybrid.nAckSeq')).readUInt32LE(0) + 1;
  await write('GVL_Hybrid.fCommand', realsBuffer(command));
  await write('GVL_Hybrid.nCommandSeq', udint(sequence));
  const ack = (await read('GVL_Hybrid.nAckSeq')).readUInt32LE(0);
  check(ack === sequence, `nAckSeq ${ack}, expected ${sequence}`);
  const position = reals(await read('GVL_Hybrid.fPosition'));
  const force = reals(await read('GVL_Hybrid.fForce'));
  check(position.every((p, k) => Math.abs(p - command[k]) < 1e-9),
    `fPosition ${position}, expected the command ${command}`);
  // Read by symbol name too (0xF009 then the value), and an unknown symbol is ADS error 0x710.
  const raw = await client.readRawByPath('GVL_Hybrid.fPosition');
  check(reals(raw).every((p, k) => p === position[k]), 'readRawByPath disagrees with the handle');
  let missing = 'no error';
  try {
    await client.getSymbol('GVL_Hybrid.fNothing');
  } catch (e) {
    missing = String(e.adsError ? e.adsError.errorCode : e.message);
  }
  check(missing === '1808', `an unknown symbol gave ${missing}, expected ADS error 1808 (0x710)`);
  await write('GVL_Hybrid.bHold', Buffer.from([1]));
  for (const h of Object.values(handles)) await client.deleteVariableHandle(h);
  await client.disconnect();
  console.log(`ads-client peer: OK device '${info.deviceName}' v${info.majorVersion}.${info.minorVersion}.${info.versionBuild}, `
    + `${Object.keys(profile).length} symbols checked, command [${command}] acknowledged `
    + `(sequence ${sequence}), position [${position}], force [${force}]`);
}

main().then(() => process.exit(0), (e) => {
  console.log(`ads-client peer: FAILED ${e.message}${e.adsError ? ` (${e.adsError.errorStr})` : ''}`
    + `${e.parentError ? `: ${e.parentError.message}` : ''}`);
  process.exit(1);
});
