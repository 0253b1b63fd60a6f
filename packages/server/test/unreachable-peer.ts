import type {
  DataChannelInitLike,
  DataChannelLike,
  PeerConnectionLike,
  SessionDescriptionLike,
} from 'fixedstep';

/**
 * A peer connection whose channels never open — no route between the peers — so joiners fall back
 * to the tunnel through the signalling hub. Records every channel it was asked for.
 */
export class UnreachablePeerConnection implements PeerConnectionLike {
  /** Every channel created, by any instance: label and options. */
  static readonly created: [string, DataChannelInitLike | undefined][] = [];
  connectionState = 'new';
  localDescription: SessionDescriptionLike | undefined;
  onicecandidate = null;
  ondatachannel = null;
  onconnectionstatechange = null;
  createDataChannel(label: string, init?: DataChannelInitLike): DataChannelLike {
    UnreachablePeerConnection.created.push([label, init]);
    return {
      label,
      readyState: 'connecting',
      bufferedAmount: 0,
      send: () => undefined,
      close: () => undefined,
      onopen: null,
      onclose: null,
      onmessage: null,
    };
  }
  createOffer(): Promise<SessionDescriptionLike> {
    return Promise.resolve({ type: 'offer', sdp: 'v=0 (never connects)' });
  }
  createAnswer(): Promise<SessionDescriptionLike> {
    return Promise.resolve({ type: 'answer', sdp: 'v=0 (never connects)' });
  }
  setLocalDescription(d: SessionDescriptionLike): Promise<void> {
    this.localDescription = { type: d.type, sdp: d.sdp ?? '' };
    return Promise.resolve();
  }
  setRemoteDescription(): Promise<void> {
    return Promise.resolve();
  }
  addIceCandidate(): Promise<void> {
    return Promise.resolve();
  }
  close(): void {
    this.connectionState = 'closed';
  }
}
