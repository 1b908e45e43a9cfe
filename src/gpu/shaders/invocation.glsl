// Where an invocation is in a dispatch that may span two dimensions: ComputePipeline::dispatch
// spreads more workgroups than the device's maxComputeWorkGroupCount[0] over y (a 2048 x 2048
// sheet has 8 million connectors, 131,000 workgroups of 64; lavapipe dispatches 65,535 in x).
// The includer declares kWorkgroupSize, its workgroup size: the specialization constant 0 of
// `layout(local_size_x_id = 0) in;`, or the fixed size. Not gl_WorkGroupSize.x: glslang folds that
// to the specialization constant's default, 1, and every workgroup past the first then
// recomputed the first's items.
uint workgroup_index() { return gl_WorkGroupID.x + gl_WorkGroupID.y * gl_NumWorkGroups.x; }
uint invocation_index() { return gl_GlobalInvocationID.x + gl_GlobalInvocationID.y * gl_NumWorkGroups.x * kWorkgroupSize; }
