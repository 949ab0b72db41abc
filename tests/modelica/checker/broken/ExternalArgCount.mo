// expect: 11: ExternalArgCount -> vl_exchange: 7 arguments, vl_exchange takes 8
within ValidLib;
impure function ExternalArgCount "One argument (the message) left out"
  input Handle handle;
  input Real values[:];
  input Boolean enabled;
  input Units unitChoice;
  output Integer status;
  output Integer counts[2];
  output Real received[3];
  external "C" status = vl_exchange(handle, values, size(values, 1), enabled, unitChoice, counts, received)
    annotation (Library = "validlib", Include = "#include \"validlib.h\"");
end ExternalArgCount;
