// The velocity model (velocity.js) with its two noise forms side by side (noise_forms.js).
kernels.velocity_forms = noiseForms(kernels.velocity, 6);
