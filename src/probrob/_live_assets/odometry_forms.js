// The odometry model (odometry.js) with its two noise forms side by side (noise_forms.js).
kernels.odometry_forms = noiseForms(kernels.odometry, 4);
