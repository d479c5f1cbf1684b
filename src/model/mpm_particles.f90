!> Material points as a structure of arrays.
!>
!> Components come first so the components of one particle are contiguous: `x(dim, n)`.
!> A 2D (plane strain) case stores 2 vector components; stress and strain store the
!> out-of-plane normal component too (4 components in 2D, 6 in 3D), Voigt order
!> xx yy zz xy [yz zx]. Tension is positive. Strain components are tensor components
!> (eps_xy, not the engineering shear gamma_xy = 2 eps_xy).
module mpm_particles
    use mpm_kinds, only: wp
    use mpm_error, only: error_type, fatal_error, exit_other
    implicit none
    private
    public :: particles_type, new_particles, nstress_of, particle_bytes, record_length, &
        pack_particles, rebuild_particles, particle_number

    !> All particles of a run.
    type :: particles_type
        integer :: n = 0
            !! number of particles
        integer :: dim = 2
            !! space dimensions
        integer :: nstress = 4
            !! stress/strain components: 4 in 2D (xx yy zz xy), 6 in 3D (xx yy zz xy yz zx)
        real(wp), allocatable :: x(:, :)
            !! position (dim, n) [m]
        real(wp), allocatable :: u(:, :)
            !! displacement since the start of the run (dim, n) [m]; kept only when the case
            !! writes it (output field or state file)
        real(wp), allocatable :: v(:, :)
            !! velocity (dim, n) [m/s]
        real(wp), allocatable :: mass(:)
            !! mass (n) [kg]; per metre of thickness in 2D [kg/m]
        real(wp), allocatable :: volume(:)
            !! current volume (n) [m3]; area in 2D [m2]
        real(wp), allocatable :: volume0(:)
            !! initial volume (n) [m3]; area in 2D [m2]
        real(wp), allocatable :: stress(:, :)
            !! Cauchy stress (nstress, n), tension positive [Pa]
        real(wp), allocatable :: strain(:, :)
            !! accumulated logarithmic-rate strain (nstress, n), tensor components [-]; kept
            !! only when the case writes it (output field or state file)
        real(wp), allocatable :: f(:, :, :)
            !! deformation gradient (dim, dim, n) [-]
        real(wp), allocatable :: lp0(:, :)
            !! initial GIMP half-size of the particle domain (dim, n) [m]
        real(wp), allocatable :: lp(:, :)
            !! current GIMP half-size of the particle domain (dim, n) [m]
        integer, allocatable :: material(:)
            !! material index into case%materials (n)
        integer :: nstate = 0
            !! material state variables per particle (0 when no material of the case has any)
        real(wp), allocatable :: state(:, :)
            !! material state (nstate, n), e.g. accumulated plastic shear strain [-]
        real(wp), allocatable :: body_force(:, :)
            !! extra body force per unit mass (dim, n), allocated only by drivers that prescribe
            !! one (manufactured solutions); added to gravity in P2G [m/s2]
        real(wp), allocatable :: affine(:, :, :)
            !! APIC affine velocity C_p = sum_i v_i grad(N_i)^T (dim, dim, n) [1/s], allocated
            !! only with solver.transfer = "apic"
        integer, allocatable :: id(:)
            !! index of each particle in the whole run (n), allocated only when the particles
            !! are spread over images (mpm_parallel); otherwise the index is the id
    end type particles_type

contains

    !> Number of stress components stored for a dimension: 4 in 2D, 6 in 3D.
    pure integer function nstress_of(dim)
        integer, intent(in) :: dim
            !! space dimensions
        if (dim == 2) then
            nstress_of = 4
        else
            nstress_of = 6
        end if
    end function nstress_of

    !> Allocate storage for n particles, zeroed (F set to the identity).
    subroutine new_particles(particles, dim, n, error, nstate)
        type(particles_type), intent(out) :: particles
            !! particles to create
        integer, intent(in) :: dim
            !! space dimensions (2 or 3)
        integer, intent(in) :: n
            !! number of particles
        type(error_type), allocatable, intent(out) :: error
            !! set when memory cannot be allocated
        integer, intent(in), optional :: nstate
            !! material state variables per particle (default 0)

        integer :: stat, d
        character(len=256) :: msg
        character(len=32) :: buf

        particles%n = n
        particles%dim = dim
        particles%nstress = nstress_of(dim)
        allocate (particles%x(dim, n), particles%u(dim, n), particles%v(dim, n), &
            particles%mass(n), particles%volume(n), particles%volume0(n), &
            particles%stress(particles%nstress, n), particles%strain(particles%nstress, n), &
            particles%f(dim, dim, n), particles%lp0(dim, n), particles%lp(dim, n), &
            particles%material(n), stat=stat, errmsg=msg)
        if (stat == 0) then
            particles%nstate = 0
            if (present(nstate)) particles%nstate = nstate
            allocate (particles%state(particles%nstate, n), stat=stat, errmsg=msg)
        end if
        if (stat /= 0) then
            write (buf, "(i0)") n
            call fatal_error(error, "cannot allocate "//trim(buf)//" particles: "//trim(msg), &
                exit_other)
            return
        end if
        particles%x = 0.0_wp
        particles%u = 0.0_wp
        particles%v = 0.0_wp
        particles%mass = 0.0_wp
        particles%volume = 0.0_wp
        particles%volume0 = 0.0_wp
        particles%stress = 0.0_wp
        particles%strain = 0.0_wp
        particles%f = 0.0_wp
        do d = 1, dim
            particles%f(d, d, :) = 1.0_wp
        end do
        particles%lp0 = 0.0_wp
        particles%lp = 0.0_wp
        particles%material = 0
        particles%state = 0.0_wp
    end subroutine new_particles

    !> The number of particle p for messages: its index in the whole run (its id when the
    !> particles are spread over images).
    pure integer function particle_number(particles, p)
        type(particles_type), intent(in) :: particles
            !! the particles
        integer, intent(in) :: p
            !! index in these particles
        particle_number = p
        if (allocated(particles%id)) particle_number = particles%id(p)
    end function particle_number

    !> Bytes of particle storage per particle (all per-particle arrays).
    pure integer function particle_bytes(particles)
        type(particles_type), intent(in) :: particles
            !! the particles

        integer :: d, ns
        integer :: real_bytes, int_bytes

        d = particles%dim
        ns = particles%nstress
        real_bytes = storage_size(1.0_wp)/8
        int_bytes = storage_size(1)/8
        ! x, v, lp0, lp (and u when kept): d each; mass, volume, volume0: 1; stress (and
        ! strain when kept): ns; f: d*d; material state: nstate
        particle_bytes = real_bytes*(4*d + 3 + ns + d*d + particles%nstate) + int_bytes
        if (allocated(particles%u)) particle_bytes = particle_bytes + real_bytes*d
        if (allocated(particles%strain)) particle_bytes = particle_bytes + real_bytes*ns
        if (allocated(particles%affine)) particle_bytes = particle_bytes + real_bytes*d*d
        if (allocated(particles%id)) particle_bytes = particle_bytes + int_bytes
    end function particle_bytes

    !> Values in the record of one particle (pack_particles): every array the particles keep.
    pure integer function record_length(particles)
        type(particles_type), intent(in) :: particles
            !! the particles
        integer :: d, ns

        d = particles%dim
        ns = particles%nstress
        ! x, v, lp0, lp; mass, volume, volume0, material; stress; F; state
        record_length = 4*d + 4 + ns + d*d + particles%nstate
        if (allocated(particles%u)) record_length = record_length + d
        if (allocated(particles%strain)) record_length = record_length + ns
        if (allocated(particles%body_force)) record_length = record_length + d
        if (allocated(particles%affine)) record_length = record_length + d*d
        if (allocated(particles%id)) record_length = record_length + 1
    end function record_length

    !> The records of the particles where `mask` is true, in index order, one after the
    !> other (integers as reals: exact below 2^53).
    subroutine pack_particles(particles, mask, buf)
        type(particles_type), intent(in) :: particles
            !! the particles
        logical, intent(in) :: mask(:)
            !! particles to pack (n)
        real(wp), allocatable, intent(out) :: buf(:)
            !! records (record_length x count(mask))

        integer :: p, k, r, d, ns

        d = particles%dim
        ns = particles%nstress
        r = record_length(particles)
        allocate (buf(r*count(mask)))
        k = 0
        do p = 1, particles%n
            if (.not. mask(p)) cycle
            call put(particles%x(:, p))
            call put(particles%v(:, p))
            call put(particles%lp0(:, p))
            call put(particles%lp(:, p))
            call put([particles%mass(p), particles%volume(p), particles%volume0(p), &
                real(particles%material(p), wp)])
            call put(particles%stress(:, p))
            call put(reshape(particles%f(:, :, p), [d*d]))
            call put(particles%state(:, p))
            if (allocated(particles%u)) call put(particles%u(:, p))
            if (allocated(particles%strain)) call put(particles%strain(:, p))
            if (allocated(particles%body_force)) call put(particles%body_force(:, p))
            if (allocated(particles%affine)) call put(reshape(particles%affine(:, :, p), [d*d]))
            if (allocated(particles%id)) call put([real(particles%id(p), wp)])
        end do

    contains

        subroutine put(values)
            real(wp), intent(in) :: values(:)
            buf(k + 1:k + size(values)) = values
            k = k + size(values)
        end subroutine put

    end subroutine pack_particles

    !> Keep the particles where `keep` is true (in their order) and append the particles of
    !> `records` (pack_particles of particles with the same arrays).
    subroutine rebuild_particles(particles, keep, records, error)
        type(particles_type), intent(inout) :: particles
            !! the particles
        logical, intent(in) :: keep(:)
            !! particles that stay (n)
        real(wp), intent(in) :: records(:)
            !! records of the arriving particles
        type(error_type), allocatable, intent(out) :: error
            !! set when memory cannot be allocated

        integer :: nkeep, nin, n, p, q, k, d, ns, r
        integer, allocatable :: kept(:)

        d = particles%dim
        ns = particles%nstress
        r = record_length(particles)
        kept = pack([(p, p = 1, particles%n)], keep)
        nkeep = size(kept)
        nin = size(records)/r
        n = nkeep + nin
        call regrow2(particles%x)
        call regrow2(particles%v)
        call regrow2(particles%lp0)
        call regrow2(particles%lp)
        call regrow1(particles%mass)
        call regrow1(particles%volume)
        call regrow1(particles%volume0)
        call regrow_int(particles%material)
        call regrow2(particles%stress)
        call regrow3(particles%f)
        call regrow2(particles%state)
        if (allocated(particles%u)) call regrow2(particles%u)
        if (allocated(particles%strain)) call regrow2(particles%strain)
        if (allocated(particles%body_force)) call regrow2(particles%body_force)
        if (allocated(particles%affine)) call regrow3(particles%affine)
        if (allocated(particles%id)) call regrow_int(particles%id)
        if (allocated(error)) return
        particles%n = n
        k = 0
        do q = 1, nin
            p = nkeep + q
            particles%x(:, p) = take(d)
            particles%v(:, p) = take(d)
            particles%lp0(:, p) = take(d)
            particles%lp(:, p) = take(d)
            particles%mass(p) = take1()
            particles%volume(p) = take1()
            particles%volume0(p) = take1()
            particles%material(p) = nint(take1())
            particles%stress(:, p) = take(ns)
            particles%f(:, :, p) = reshape(take(d*d), [d, d])
            particles%state(:, p) = take(particles%nstate)
            if (allocated(particles%u)) particles%u(:, p) = take(d)
            if (allocated(particles%strain)) particles%strain(:, p) = take(ns)
            if (allocated(particles%body_force)) particles%body_force(:, p) = take(d)
            if (allocated(particles%affine)) particles%affine(:, :, p) = reshape(take(d*d), [d, d])
            if (allocated(particles%id)) particles%id(p) = nint(take1())
        end do

    contains

        function take(m) result(values)
            integer, intent(in) :: m
            real(wp) :: values(m)
            values = records(k + 1:k + m)
            k = k + m
        end function take

        real(wp) function take1()
            take1 = records(k + 1)
            k = k + 1
        end function take1

        subroutine regrow1(a)
            real(wp), allocatable, intent(inout) :: a(:)
            real(wp), allocatable :: b(:)
            integer :: stat
            character(len=256) :: msg
            if (allocated(error)) return
            allocate (b(n), stat=stat, errmsg=msg)
            if (stat /= 0) then
                call failed(msg)
                return
            end if
            b(1:nkeep) = a(kept)
            call move_alloc(b, a)
        end subroutine regrow1

        subroutine regrow_int(a)
            integer, allocatable, intent(inout) :: a(:)
            integer, allocatable :: b(:)
            integer :: stat
            character(len=256) :: msg
            if (allocated(error)) return
            allocate (b(n), stat=stat, errmsg=msg)
            if (stat /= 0) then
                call failed(msg)
                return
            end if
            b(1:nkeep) = a(kept)
            call move_alloc(b, a)
        end subroutine regrow_int

        subroutine regrow2(a)
            real(wp), allocatable, intent(inout) :: a(:, :)
            real(wp), allocatable :: b(:, :)
            integer :: stat
            character(len=256) :: msg
            if (allocated(error)) return
            allocate (b(size(a, 1), n), stat=stat, errmsg=msg)
            if (stat /= 0) then
                call failed(msg)
                return
            end if
            b(:, 1:nkeep) = a(:, kept)
            call move_alloc(b, a)
        end subroutine regrow2

        subroutine regrow3(a)
            real(wp), allocatable, intent(inout) :: a(:, :, :)
            real(wp), allocatable :: b(:, :, :)
            integer :: stat
            character(len=256) :: msg
            if (allocated(error)) return
            allocate (b(size(a, 1), size(a, 2), n), stat=stat, errmsg=msg)
            if (stat /= 0) then
                call failed(msg)
                return
            end if
            b(:, :, 1:nkeep) = a(:, :, kept)
            call move_alloc(b, a)
        end subroutine regrow3

        subroutine failed(msg)
            character(len=*), intent(in) :: msg
            call fatal_error(error, "cannot allocate the particles of this image after the "// &
                "exchange with its neighbours: "//trim(msg), exit_other)
        end subroutine failed

    end subroutine rebuild_particles

end module mpm_particles
