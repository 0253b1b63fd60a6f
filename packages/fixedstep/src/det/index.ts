export { Random } from './random.js';
export { Fnv1a64, fnv1a64, fnv1a64Hex } from './hash.js';
export { ByteWriter, ByteReader } from './bytes.js';
