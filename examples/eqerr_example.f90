! The equivalent-error test from Fortran, on the example flight.
! Build against an installed igea (the module igea comes with it):
!   gfortran $(pkg-config --variable=fflags igea) eqerr_example.f90 \
!     $(pkg-config --libs igea) -o eqerr_example_f
! Run from examples/ (or give the flight's directory as the argument):
!   ./eqerr_example_f flight
! Reads S.txt (m x N), dw.txt (m), sigma.txt (m) and spec.txt (N) of the
! directory ('#' lines are comments), calls igea_eqerr_run with the
! library's defaults and prints the verdict, c and T; exits 0 accepted,
! 1 rejected, 2 on an error (with igea_strerror's text).
program eqerr_example
  use, intrinsic :: iso_c_binding
  use igea
  implicit none
  character(len=4096) :: dir
  real(c_double), allocatable :: S(:,:), dw(:), sigma(:), spec(:), lambda(:), P(:,:), &
       xhat(:), z(:)
  integer(c_int), allocatable :: reject(:)
  real(c_double) :: opts(IGEA_EQERR_OPT_LEN), info(IGEA_STATS_INFO_LEN), rms(3)
  integer :: m, n
  integer(c_int) :: st

  dir = 'flight'
  if (command_argument_count() >= 1) call get_command_argument(1, dir)
  m = 0
  n = 0
  call read_vector(trim(dir) // '/dw.txt', dw, m)
  call read_vector(trim(dir) // '/sigma.txt', sigma, m)
  call read_vector(trim(dir) // '/spec.txt', spec, n)
  allocate(S(m, n), lambda(n), P(n, n), xhat(n), z(n), reject(n))
  call read_matrix(trim(dir) // '/S.txt', S)

  st = igea_eqerr_defaults(opts)
  ! opts(IGEAF_EQERR_OPT_ALPHA) = 0.01d0    (1-based indices: IGEAF_*)
  st = igea_eqerr_run(int(m, c_int), int(n, c_int), S, int(m, c_int), dw, sigma, 1_c_int, &
       spec, opts, lambda, P, int(n, c_int), xhat, z, reject, info, rms=rms)
  if (st /= 0) then
    write (*, '(a, i0, 2a)') 'igea_eqerr_run: status ', st, ': ', c_string(igea_strerror(st))
    stop 2
  end if
  if (info(IGEAF_STATS_INFO_PASSED) == 1d0) then
    write (*, '(a)') 'verdict: ACCEPTED'
  else
    write (*, '(a)') 'verdict: REJECTED'
  end if
  write (*, '(a, es24.16)') 'c = ', info(IGEAF_STATS_INFO_SCALE)
  write (*, '(a, es24.16, a, i0, a)') 'T = ', info(IGEAF_STATS_INFO_CHI2), ' with ', &
       nint(info(IGEAF_STATS_INFO_DOF)), ' dof'
  if (info(IGEAF_STATS_INFO_PASSED) /= 1d0) stop 1

contains

  ! The text of a C string (a const char * result of the library).
  function c_string(p) result(s)
    type(c_ptr), intent(in) :: p
    character(len=:), allocatable :: s
    character(kind=c_char), pointer :: a(:)
    integer :: i, k
    k = int(igea_c_strlen(p))
    call c_f_pointer(p, a, [k])
    allocate(character(len=k) :: s)
    do i = 1, k
      s(i:i) = a(i)
    end do
  end function c_string

  ! Lines of a text file that are neither empty nor '#' comments, counted.
  integer function data_lines(path)
    character(len=*), intent(in) :: path
    character(len=65536) :: line
    integer :: u, ios
    data_lines = 0
    open (newunit=u, file=path, status='old', action='read', iostat=ios)
    if (ios /= 0) then
      write (*, '(2a)') 'cannot open ', path
      stop 2
    end if
    do
      read (u, '(a)', iostat=ios) line
      if (ios /= 0) exit
      line = adjustl(line)
      if (len_trim(line) > 0 .and. line(1:1) /= '#') data_lines = data_lines + 1
    end do
    close (u)
  end function data_lines

  ! A one-column file into v (allocated), its length into k; a length
  ! that differs from a k already set (k > 0 on entry) stops.
  subroutine read_vector(path, v, k)
    character(len=*), intent(in) :: path
    real(c_double), allocatable, intent(out) :: v(:)
    integer, intent(inout) :: k
    real(c_double), allocatable :: a(:,:)
    integer :: rows
    rows = data_lines(path)
    allocate(a(rows, 1))
    call read_matrix(path, a)
    v = a(:, 1)
    if (k > 0 .and. k /= rows) then
      write (*, '(a, 2(a, i0))') path, ': rows ', rows, ', expected ', k
      stop 2
    end if
    k = rows
  end subroutine read_vector

  ! The data lines of a file into the rows of a (its shape is the file's).
  subroutine read_matrix(path, a)
    character(len=*), intent(in) :: path
    real(c_double), intent(out) :: a(:,:)
    real(c_double) :: extra(size(a, 2) + 1)
    character(len=65536) :: line
    integer :: u, ios, ios2, i
    if (data_lines(path) /= size(a, 1)) then
      write (*, '(2a, i0, a)') path, ': expected ', size(a, 1), ' rows'
      stop 2
    end if
    open (newunit=u, file=path, status='old', action='read')
    i = 0
    do while (i < size(a, 1))
      read (u, '(a)') line
      line = adjustl(line)
      if (len_trim(line) == 0 .or. line(1:1) == '#') cycle
      i = i + 1
      read (line, *, iostat=ios) a(i, :)
      if (ios == 0) then
        read (line, *, iostat=ios2) extra
        if (ios2 == 0) ios = 1  ! more numbers than columns
      end if
      if (ios /= 0) then
        write (*, '(a, a, i0, a, i0, a)') path, ': data row ', i, ': expected ', size(a, 2), &
             ' numbers'
        stop 2
      end if
    end do
    close (u)
  end subroutine read_matrix

end program eqerr_example
