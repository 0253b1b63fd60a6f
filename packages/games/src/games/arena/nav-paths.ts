/** The path length between two nodes with no path between them. */
export const UNREACHABLE = 0x7fffffff;

/**
 * All-pairs shortest path lengths of a graph of `n` nodes with up to 8 edges each (`adj[v × 8 + k]`:
 * the k-th neighbour of v, -1 after the last; `cost[v × 8 + k]`: that edge's length, an integer):
 * the length from node i to node j at `i × n + j`, {@link UNREACHABLE} where there is no path.
 * Dijkstra from every node; integer costs, so the lengths are exact.
 */
export function shortestPaths(n: number, adj: Int32Array, cost: Int32Array): Int32Array {
  const dist = new Int32Array(n * n).fill(UNREACHABLE);
  // Dijkstra from every node with a binary heap of (cost, node), ties broken by node index.
  const heapCost = new Int32Array(n * 8 + 1);
  const heapNode = new Int32Array(n * 8 + 1);
  for (let s = 0; s < n; s++) {
    const row = s * n;
    let size = 0;
    const push = (c: number, v: number): void => {
      let i = size++;
      while (i > 0) {
        const p = (i - 1) >> 1;
        if (heapCost[p]! < c || (heapCost[p] === c && heapNode[p]! <= v)) break;
        heapCost[i] = heapCost[p]!;
        heapNode[i] = heapNode[p]!;
        i = p;
      }
      heapCost[i] = c;
      heapNode[i] = v;
    };
    const pop = (): void => {
      const c = heapCost[--size]!;
      const v = heapNode[size]!;
      let i = 0;
      for (;;) {
        let m = 2 * i + 1;
        if (m >= size) break;
        if (
          m + 1 < size &&
          (heapCost[m + 1]! < heapCost[m]! ||
            (heapCost[m + 1] === heapCost[m] && heapNode[m + 1]! < heapNode[m]!))
        ) {
          m++;
        }
        if (c < heapCost[m]! || (c === heapCost[m] && v <= heapNode[m]!)) break;
        heapCost[i] = heapCost[m]!;
        heapNode[i] = heapNode[m]!;
        i = m;
      }
      heapCost[i] = c;
      heapNode[i] = v;
    };
    dist[row + s] = 0;
    push(0, s);
    while (size > 0) {
      const c = heapCost[0]!;
      const v = heapNode[0]!;
      pop();
      if (c > dist[row + v]!) continue;
      for (let k = 0; k < 8; k++) {
        const w = adj[v * 8 + k]!;
        if (w < 0) break;
        const nc = c + cost[v * 8 + k]!;
        if (nc < dist[row + w]!) {
          dist[row + w] = nc;
          push(nc, w);
        }
      }
    }
  }
  return dist;
}
