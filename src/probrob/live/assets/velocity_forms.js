// Tables 5.1 and 5.3 in both noise forms (velocity.js with noise_forms.js): velocity_noise_forms_live.
kernels.velocity_forms = noiseForms(kernels.velocity, 6);
