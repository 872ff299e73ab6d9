// Live positions: the hook for the live-tracking API (GET /v1/maps/{id}/positions and its
// Server-Sent Events stream), which this server does not have yet. The viewer calls
// followFloor on every floor change and the stop function it returned before the next; an
// implementation draws each device on `layer` (trail, uncertainty circle) for floor `floorId`
// and moves it between floors as its fixes say. Until then nothing is drawn and no request is
// made, so no position is ever invented.
export function followFloor({ mapId, floorId, layer }) {
  void mapId; void floorId; void layer;
  return () => {};
}
