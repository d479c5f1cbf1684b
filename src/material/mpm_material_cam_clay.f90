!> Modified Cam Clay (Roscoe and Burland 1968): the critical-state model of a clay, in
!> effective stresses, for drained and undrained (constant volume) loading.
!>
!> With p = -tr(sigma)/3 the mean stress (compression positive) and q = sqrt(3 J2) the
!> deviator stress, the yield surface is the ellipse f = q^2 / M^2 + p (p - pc) <= 0 through
!> the origin and the preconsolidation pressure pc, whose top meets the critical state line
!> q = M p at p = pc / 2. The flow is associated. The compression indices are
!> those of the e - ln p plane, lambda (normal compression) and kappa (swelling), taken per
!> unit of the initial specific volume v0 = 1 + e0 (lambda* = lambda / v0, kappa* =
!> kappa / v0: the indices of the ln v - ln p form, constant in the run):
!>
!> - elastic: p = p_n exp(d eps_v^e / kappa*) (the bulk modulus K = p / kappa*, integrated
!>   exactly over the step), the shear modulus G = 3 K (1 - 2 nu) / (2 (1 + nu)) at the
!>   start of the step;
!> - hardening: pc = pc_n exp(d eps_v^p / (lambda* - kappa*)), eps_v the volumetric
!>   strain, compression positive (the logarithmic strain the strain increments add up to).
!>
!> Below p_min the bulk modulus is held at p_min / kappa* (a stress-free start and states
!> near the apex keep a stiffness; p_min is small against the stresses of the problem).
!>
!> The return is implicit (closest point in the energy norm): with the plastic volumetric
!> strain e and the multiplier dl the unknowns, e = dl (2 p - pc) and f(p, q, pc) = 0,
!> q = q_trial / (1 + 6 G dl / M^2), solved by Newton's method from the elastic trial. A
!> step whose Newton iterations do not converge is split in halves (up to 2^8 parts).
!>
!> The preconsolidation pressure of a particle is set at its first update from the stress it
!> has then (the initial stress of the case): pc = OCR (p + q^2 / (M^2 p)), the ellipse
!> through that stress, times the overconsolidation ratio (at least OCR p_min).
!>
!> Closed forms the element tests check (tests/unit/test_mpm_material_cam_clay.f90), for a
!> normally consolidated clay from an isotropic p0: undrained, p / p0 = (M^2 / (M^2 +
!> eta^2))^(1 - kappa / lambda), eta = q / p, failing at q = M p; drained triaxial
!> compression (p = p0 + q / 3), eps_v = lambda* ln(p / p0) + (lambda* - kappa*) ln(1 +
!> eta^2 / M^2), failing at p = 3 p0 / (3 - M).
!>
!> The stored energy is kappa* p (the integral of p d eps_v^e; below p_min that of the held
!> modulus) plus q^2 / (6 G)
!> at the current shear modulus: the law is hypoelastic in shear (G grows with p), so a
!> closed elastic cycle that changes p books a small share of its shear work as dissipated.
!>
!> State of a particle: state(1) = the accumulated plastic shear strain eps_q^p = sum dl 2 q /
!> M^2 [-] (first, as in the other plastic materials: the `plastic_strain` output field),
!> state(2) = pc [Pa] (0 before the first update; a state file of a stage whose material had
!> another type gives zeros, mpm_state).
!>
!> `materials[i].type = "cam_clay"` (alias "mcc"): keys `M`, `lambda`,
!> `kappa`, `e0`, `nu`, `rho`, `OCR`, `p_min`.
module mpm_material_cam_clay
    use mpm_kinds, only: wp
    use mpm_error, only: error_type
    use mpm_strings, only: fmt_real
    use mpm_case_cursor, only: cursor_type
    use mpm_material, only: material_type, material_key_width, work_plastic
    use mpm_stress, only: mean_and_deviator, add_jaumann_rotation
    implicit none
    private
    public :: cam_clay_material_type, new_cam_clay_material

    real(wp), parameter :: sqrt3 = sqrt(3.0_wp)
    integer, parameter :: max_halvings = 8
        !! a step is split into at most 2**max_halvings parts
    integer, parameter :: max_newton = 40
        !! Newton iterations of one return

    !> Modified Cam Clay with hypoelastic bulk modulus K = p / kappa*.
    type, extends(material_type) :: cam_clay_material_type
        real(wp) :: m = 0.0_wp
            !! slope of the critical state line in p - q [-]
        real(wp) :: lambda = 0.0_wp
            !! slope of the normal compression line in e - ln p [-]
        real(wp) :: kappa = 0.0_wp
            !! slope of the swelling lines in e - ln p [-]
        real(wp) :: e0 = 0.0_wp
            !! initial void ratio [-]
        real(wp) :: poisson = 0.0_wp
            !! Poisson's ratio of the elastic part [-]
        real(wp) :: ocr = 1.0_wp
            !! overconsolidation ratio pc / (pc of the ellipse through the initial stress) [-]
        real(wp) :: p_min = 1000.0_wp
            !! mean stress below which the bulk modulus is held at p_min / kappa* [Pa]
    contains
        procedure, nopass :: names => cam_clay_names
        procedure, nopass :: keys => cam_clay_keys
        procedure :: read => cam_clay_read
        procedure :: wave_speed => cam_clay_wave_speed
        procedure :: wave_speed_at => cam_clay_wave_speed_at
        procedure :: speed_varies => cam_clay_speed_varies
        procedure :: writes_plastic_strain => cam_clay_writes_plastic_strain
        procedure :: summary => cam_clay_summary
        procedure :: update_stress => cam_clay_update_stress
        procedure :: nstate => cam_clay_nstate
        procedure :: work_kind => cam_clay_work_kind
        procedure :: elastic_energy_block => cam_clay_energy_block
        procedure :: at_rest_ratio => cam_clay_at_rest_ratio
        !> lambda* = lambda / (1 + e0).
        procedure :: lambda_star
        !> kappa* = kappa / (1 + e0).
        procedure :: kappa_star
        !> The shear modulus at a mean stress p.
        procedure :: shear_at
    end type cam_clay_material_type

contains

    !> Names accepted for `type`.
    pure subroutine cam_clay_names(list)
        character(len=material_key_width), allocatable, intent(out) :: list(:)
            !! the names

        list = [character(len=material_key_width) :: "cam_clay", "mcc"]
    end subroutine cam_clay_names

    !> Keys of a Cam Clay material.
    pure subroutine cam_clay_keys(list)
        character(len=material_key_width), allocatable, intent(out) :: list(:)
            !! the keys

        list = [character(len=material_key_width) :: "name", "type", "M", "lambda", "kappa", &
            "e0", "nu", "rho", "OCR", "p_min"]
    end subroutine cam_clay_keys

    !> M, the indices, e0, nu, rho, OCR and p_min; kappa < lambda.
    subroutine cam_clay_read(self, item, error)
        class(cam_clay_material_type), intent(inout) :: self
            !! the material
        type(cursor_type), intent(in) :: item
            !! the material object ("materials[i]")
        type(error_type), allocatable, intent(out) :: error
            !! first error found

        call item%get_real("M", self%m, error, required=.true., above=0.0_wp, below=3.0_wp)
        if (allocated(error)) return
        call item%get_real("lambda", self%lambda, error, required=.true., above=0.0_wp)
        if (allocated(error)) return
        call item%get_real("kappa", self%kappa, error, required=.true., above=0.0_wp)
        if (allocated(error)) return
        if (self%kappa >= self%lambda) then
            call item%fail(error, item%key_path("kappa")//" = "//fmt_real(self%kappa) &
                //" is not below "//item%key_path("lambda")//" = "//fmt_real(self%lambda) &
                //": the swelling lines must be flatter than the normal compression line " &
                //"(kappa < lambda; clays have kappa / lambda of about 0.1 to 0.3)")
            return
        end if
        call item%get_real("e0", self%e0, error, required=.true., above=0.0_wp)
        if (allocated(error)) return
        call item%get_real("nu", self%poisson, error, required=.true., at_least=0.0_wp, &
            below=0.5_wp)
        if (allocated(error)) return
        call item%get_real("rho", self%density, error, required=.true., above=0.0_wp, &
            unit="kg/m3")
        if (allocated(error)) return
        call item%get_real("OCR", self%ocr, error, at_least=1.0_wp)
        if (allocated(error)) return
        call item%get_real("p_min", self%p_min, error, above=0.0_wp, unit="Pa")
    end subroutine cam_clay_read

    !> Construct a Cam Clay material (tests, tools).
    pure subroutine new_cam_clay_material(mat, m, lambda, kappa, e0, poisson, density, ocr, &
            p_min)
        type(cam_clay_material_type), intent(out) :: mat
            !! the material
        real(wp), intent(in) :: m, lambda, kappa, e0, poisson, density, ocr, p_min
            !! M, lambda, kappa, e0, nu [-], rho [kg/m3], OCR [-], p_min [Pa]

        mat%m = m
        mat%lambda = lambda
        mat%kappa = kappa
        mat%e0 = e0
        mat%poisson = poisson
        mat%density = density
        mat%ocr = ocr
        mat%p_min = p_min
    end subroutine new_cam_clay_material

    !> lambda / (1 + e0).
    pure real(wp) function lambda_star(self)
        class(cam_clay_material_type), intent(in) :: self
            !! the material
        lambda_star = self%lambda/(1.0_wp + self%e0)
    end function lambda_star

    !> kappa / (1 + e0).
    pure real(wp) function kappa_star(self)
        class(cam_clay_material_type), intent(in) :: self
            !! the material
        kappa_star = self%kappa/(1.0_wp + self%e0)
    end function kappa_star

    !> G = 3 K (1 - 2 nu) / (2 (1 + nu)), K = max(p, p_min) / kappa*.
    pure real(wp) function shear_at(self, p)
        class(cam_clay_material_type), intent(in) :: self
            !! the material
        real(wp), intent(in) :: p
            !! mean stress, compression positive [Pa]
        shear_at = 1.5_wp*max(p, self%p_min)/self%kappa_star()*(1.0_wp - 2.0_wp*self%poisson) &
            /(1.0_wp + self%poisson)
    end function shear_at

    !> P-wave speed at p_min, the least it has (the time step follows each particle's stress,
    !> wave_speed_at).
    pure real(wp) function cam_clay_wave_speed(self)
        class(cam_clay_material_type), intent(in) :: self
            !! the material
        cam_clay_wave_speed = speed_at_mean(self, self%p_min)
    end function cam_clay_wave_speed

    !> P-wave speed sqrt((K + 4 G / 3) / rho) at the mean stress p.
    pure real(wp) function speed_at_mean(self, p)
        class(cam_clay_material_type), intent(in) :: self
            !! the material
        real(wp), intent(in) :: p
            !! mean stress, compression positive [Pa]
        speed_at_mean = sqrt((max(p, self%p_min)/self%kappa_star() &
            + 4.0_wp*self%shear_at(p)/3.0_wp)/self%density)
    end function speed_at_mean

    !> P-wave speed at a particle's stress: the stiffness grows with the mean stress.
    pure real(wp) function cam_clay_wave_speed_at(self, stress, state)
        class(cam_clay_material_type), intent(in) :: self
            !! the material
        real(wp), intent(in) :: stress(:)
            !! the particle's stress [Pa]
        real(wp), intent(in) :: state(:)
            !! its state (unused)
        cam_clay_wave_speed_at = speed_at_mean(self, -(stress(1) + stress(2) + stress(3)) &
            /3.0_wp)
    end function cam_clay_wave_speed_at

    !> The wave speed follows the stress.
    pure logical function cam_clay_speed_varies(self)
        class(cam_clay_material_type), intent(in) :: self
            !! the material
        cam_clay_speed_varies = .true.
    end function cam_clay_speed_varies

    !> The plastic shear strain is the state this material writes.
    pure logical function cam_clay_writes_plastic_strain(self)
        class(cam_clay_material_type), intent(in) :: self
            !! the material
        cam_clay_writes_plastic_strain = .true.
    end function cam_clay_writes_plastic_strain

    !> The critical state line, the indices, elasticity and the initial state.
    pure subroutine cam_clay_summary(self, text)
        class(cam_clay_material_type), intent(in) :: self
            !! the material
        character(len=:), allocatable, intent(out) :: text
            !! the lines

        text = "M = "//fmt_real(self%m)//", lambda = "//fmt_real(self%lambda)//", kappa = " &
            //fmt_real(self%kappa)//", e0 = "//fmt_real(self%e0)//", nu = " &
            //fmt_real(self%poisson)//", rho = "//fmt_real(self%density)//" kg/m3" &
            //new_line("a")//"    pc = OCR x the ellipse through the initial stress, OCR = " &
            //fmt_real(self%ocr)//"; K = p / "//fmt_real(self%kappa_star(), 4) &
            //" (at least p_min = "//fmt_real(self%p_min)//" Pa), c_p = " &
            //fmt_real(self%wave_speed(), 4)//" m/s at p_min" //new_line("a")
    end subroutine cam_clay_summary

    !> Two state values: the plastic shear strain and pc.
    pure integer function cam_clay_nstate(self)
        class(cam_clay_material_type), intent(in) :: self
            !! the material
        cam_clay_nstate = 2
    end function cam_clay_nstate

    !> Plastic: the work beyond the stored elastic energy is dissipated.
    pure integer function cam_clay_work_kind(self)
        class(cam_clay_material_type), intent(in) :: self
            !! the material
        cam_clay_work_kind = work_plastic
    end function cam_clay_work_kind

    !> K0 of a normally consolidated clay, Jaky's 1 - sin(phi_cs), sin(phi_cs) = 3 M / (6 + M)
    !> (the friction angle of the critical state line in triaxial compression).
    pure real(wp) function cam_clay_at_rest_ratio(self)
        class(cam_clay_material_type), intent(in) :: self
            !! the material
        cam_clay_at_rest_ratio = 1.0_wp - 3.0_wp*self%m/(6.0_wp + self%m)
    end function cam_clay_at_rest_ratio

    !> Stored energy per unit volume: kappa* p + q^2 / (6 G(p)) (below p_min, where K is
    !> held, kappa* (p^2 + p_min^2) / (2 p_min), the integral of p dp / K continued).
    pure subroutine cam_clay_energy_block(self, n, stress, state, density)
        class(cam_clay_material_type), intent(in) :: self
            !! the material
        integer, intent(in) :: n
            !! particles in the block
        real(wp), intent(in) :: stress(:, :)
            !! Cauchy stresses [Pa]
        real(wp), intent(in) :: state(:, :)
            !! material states (unused)
        real(wp), intent(out) :: density(:)
            !! stored elastic energy per unit volume [J/m3]

        real(wp) :: mean, dev(6), radius, p
        integer :: j, nc

        nc = size(stress, 1)
        do j = 1, n
            call mean_and_deviator(stress(:, j), mean, dev(1:nc), radius)
            p = -mean
            if (p >= self%p_min) then
                density(j) = self%kappa_star()*p
            else
                ! the bulk modulus p_min / kappa* below p_min: the same integral, continuous
                density(j) = self%kappa_star()*(p**2 + self%p_min**2)/(2.0_wp*self%p_min)
            end if
            density(j) = density(j) + 3.0_wp*radius**2/(6.0_wp*self%shear_at(p))
        end do
    end subroutine cam_clay_energy_block

    !> Objective rotation, then the strain increment in parts small enough for the return to
    !> converge (one part nearly always).
    pure subroutine cam_clay_update_stress(self, stress, dstrain, omega, dt, state)
        class(cam_clay_material_type), intent(in) :: self
            !! the material
        real(wp), intent(inout) :: stress(:)
            !! Cauchy stress, 4 (2D) or 6 (3D) components, tension positive [Pa]
        real(wp), intent(in) :: dstrain(:)
            !! strain increment, tensor components [-]
        real(wp), intent(in) :: omega(3)
            !! spin increment W dt (xy, yz, zx) [-]
        real(wp), intent(in) :: dt
            !! time step [s] (unused: rate independent)
        real(wp), intent(inout) :: state(:)
            !! state(1) plastic shear strain [-], state(2) pc [Pa]

        real(wp) :: start(size(stress)), start_state(2), mean, dev(6), radius, p
        integer :: parts, part, halving
        logical :: ok

        call add_jaumann_rotation(stress, omega)
        if (state(2) <= 0.0_wp) then
            call mean_and_deviator(stress, mean, dev(1:size(stress)), radius)
            p = -mean
            if (p > self%p_min) then
                state(2) = self%ocr*(p + 3.0_wp*radius**2/(self%m**2*p))
            else
                state(2) = self%ocr*self%p_min
            end if
        end if
        start = stress
        start_state = state(1:2)
        do halving = 0, max_halvings
            parts = 2**halving
            ok = .true.
            do part = 1, parts
                call return_part(self, stress, dstrain/real(parts, wp), state, ok)
                if (.not. ok) exit
            end do
            if (ok) return
            stress = start
            state(1:2) = start_state
        end do
        ! not reached in practice (a step of 2^8 parts whose returns do not converge): the
        ! parts whose Newton iterations failed keep their elastic trial, outside the surface by
        ! what one part's strain moves it; the next step's return brings the stress back
        do part = 1, parts
            call return_part(self, stress, dstrain/real(parts, wp), state, ok)
            if (.not. ok) call elastic_part(self, stress, dstrain/real(parts, wp))
        end do
    end subroutine cam_clay_update_stress

    !> One part of a step: the elastic trial and, outside the ellipse, the implicit return.
    pure subroutine return_part(self, stress, de, state, ok)
        class(cam_clay_material_type), intent(in) :: self
            !! the material
        real(wp), intent(inout) :: stress(:)
            !! stress [Pa], rotated
        real(wp), intent(in) :: de(:)
            !! strain increment of the part [-]
        real(wp), intent(inout) :: state(:)
            !! plastic shear strain, pc
        logical, intent(out) :: ok
            !! whether the return converged

        real(wp) :: pbase, shift, g, dev_trial(6), q_trial, dev_e
        real(wp) :: kstar, theta, m2, pc_n, e, dl, p, pc, q, r1, r2, j11, j12, j21, j22, det
        real(wp) :: de_step, dl_step, dp, dpc, scale, dq
        integer :: n, it

        n = size(stress)
        ok = .true.
        kstar = self%kappa_star()
        theta = self%lambda_star() - kstar
        m2 = self%m**2
        call elastic_trial(self, stress, de, dev_trial(1:n), pbase, shift, g, dev_e)
        q_trial = sqrt(1.5_wp*(sum(dev_trial(1:3)**2) + 2.0_wp*sum(dev_trial(4:n)**2)))
        pc_n = state(2)
        p = pbase*exp(dev_e/kstar) - shift
        if (q_trial**2/m2 + p*(p - pc_n) <= 0.0_wp) then
            call set_stress(stress, dev_trial(1:n), p)
            return
        end if
        ! Newton on (e, dl): r1 = e - dl (2 p - pc), r2 = q^2 / M^2 + p (p - pc)
        e = 0.0_wp
        dl = 0.0_wp
        scale = pc_n**2
        do it = 1, max_newton
            p = pbase*exp((dev_e - e)/kstar) - shift
            pc = pc_n*exp(e/theta)
            q = q_trial/(1.0_wp + 6.0_wp*g*dl/m2)
            r1 = e - dl*(2.0_wp*p - pc)
            r2 = q**2/m2 + p*(p - pc)
            if (abs(r1) <= 1.0e-13_wp .and. abs(r2) <= 1.0e-12_wp*scale) exit
            dp = -(p + shift)/kstar
            dpc = pc/theta
            dq = -q*(6.0_wp*g/m2)/(1.0_wp + 6.0_wp*g*dl/m2)
            j11 = 1.0_wp - dl*(2.0_wp*dp - dpc)
            j12 = -(2.0_wp*p - pc)
            j21 = dp*(2.0_wp*p - pc) - p*dpc
            j22 = 2.0_wp*q*dq/m2
            det = j11*j22 - j12*j21
            if (abs(det) <= tiny(1.0_wp) .or. .not. (abs(det) < huge(1.0_wp))) then
                ok = .false.
                return
            end if
            de_step = -(j22*r1 - j12*r2)/det
            dl_step = -(-j21*r1 + j11*r2)/det
            e = e + de_step
            dl = max(dl + dl_step, 0.5_wp*dl)
        end do
        if (it > max_newton .or. .not. (abs(e) < 1.0_wp)) then
            ok = .false.
            return
        end if
        p = pbase*exp((dev_e - e)/kstar) - shift
        pc = pc_n*exp(e/theta)
        q = q_trial/(1.0_wp + 6.0_wp*g*dl/m2)
        call set_stress(stress, dev_trial(1:n)/(1.0_wp + 6.0_wp*g*dl/m2), p)
        state(2) = pc
        state(1) = state(1) + dl*2.0_wp*q/m2
    end subroutine return_part

    !> The elastic trial of a part, whatever the yield surface (the fallback of a part whose
    !> return did not converge).
    pure subroutine elastic_part(self, stress, de)
        class(cam_clay_material_type), intent(in) :: self
            !! the material
        real(wp), intent(inout) :: stress(:)
            !! stress [Pa]
        real(wp), intent(in) :: de(:)
            !! strain increment of the part [-]

        real(wp) :: dev_trial(6), pbase, shift, g, dev_e
        integer :: n

        n = size(stress)
        call elastic_trial(self, stress, de, dev_trial(1:n), pbase, shift, g, dev_e)
        call set_stress(stress, dev_trial(1:n), pbase*exp(dev_e/self%kappa_star()) - shift)
    end subroutine elastic_part

    !> The pieces of the elastic trial of a part: the deviator s + 2 G de_dev, the base of the
    !> exact volumetric law p = pbase exp(d eps_v / kappa*) - shift (pbase = max(p, p_min),
    !> shift = pbase - p), G at the start of the part and d eps_v (compression positive).
    pure subroutine elastic_trial(self, stress, de, dev_trial, pbase, shift, g, dev_e)
        class(cam_clay_material_type), intent(in) :: self
            !! the material
        real(wp), intent(in) :: stress(:)
            !! stress at the start of the part [Pa]
        real(wp), intent(in) :: de(:)
            !! strain increment of the part [-]
        real(wp), intent(out) :: dev_trial(:)
            !! trial deviator, as many components as stress [Pa]
        real(wp), intent(out) :: pbase, shift
            !! base and shift of the volumetric law [Pa]
        real(wp), intent(out) :: g
            !! shear modulus of the part [Pa]
        real(wp), intent(out) :: dev_e
            !! volumetric strain increment, compression positive [-]

        real(wp) :: mean, dev(6), radius, pn
        integer :: n

        n = size(stress)
        call mean_and_deviator(stress, mean, dev(1:n), radius)
        pn = -mean
        pbase = max(pn, self%p_min)
        shift = pbase - pn
        g = self%shear_at(pn)
        dev_e = -(de(1) + de(2) + de(3))
        dev_trial = dev(1:n) + 2.0_wp*g*de
        dev_trial(1:3) = dev_trial(1:3) + 2.0_wp*g*dev_e/3.0_wp
    end subroutine elastic_trial

    !> sigma = s - p I.
    pure subroutine set_stress(stress, dev, p)
        real(wp), intent(out) :: stress(:)
            !! stress [Pa]
        real(wp), intent(in) :: dev(:)
            !! deviator [Pa]
        real(wp), intent(in) :: p
            !! mean stress, compression positive [Pa]

        stress = dev
        stress(1:3) = stress(1:3) - p
    end subroutine set_stress

end module mpm_material_cam_clay
