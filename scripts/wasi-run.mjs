#!/usr/bin/env node
// Runs a wasm32-wasip1 program (a test binary) under Node's WASI, so the core's WebAssembly
// SIMD kernels are tested as WebAssembly: cargo uses it as the target's runner
// (.cargo/config.toml). Usage: scripts/wasi-run.mjs PROGRAM.wasm [ARGS...]
import { readFile } from 'node:fs/promises';
import process from 'node:process';
import { WASI } from 'node:wasi';

const [program, ...args] = process.argv.slice(2);
const wasi = new WASI({ version: 'preview1', args: [program, ...args], env: {}, returnOnExit: true });
const module = await WebAssembly.compile(await readFile(program));
const instance = await WebAssembly.instantiate(module, wasi.getImportObject());
process.exitCode = wasi.start(instance);
